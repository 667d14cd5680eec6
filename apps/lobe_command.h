// `glossyhr lobe`: project the lobe a material reflects for one incident direction into a chosen
// directional basis and report what accuracy costs (size, time, errors), optionally as JSON and as a
// VTK surface.
#pragma once
#include <optional>
#include <string>

struct LobeArgs {
  double exponent = 100.0, specular = 0.5, diffuse = 0.0, incidentDeg = 30.0, azimuthDeg = 0.0;
  std::string basis = "haar", refiner = "relative";
  std::optional<double> eps, floor;  // empty: not given (every given value is checked, none ignored)
  std::optional<int> minLevel, maxLevel, level, order, quadrature;
  bool noHints = false, json = false;
  std::string out;
};

/// Validates (hr::InputError naming the option), measures, prints; returns the exit code.
int runLobe(const LobeArgs& a);
