// Illumination Samples without reflection in layers, and an extension's statistic by name: what the
// layers tests of both hosts compare against (every leaf gets its whole sample list).
#pragma once
#include <glossy/illumination_samples.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <span>
#include <string>

namespace testutil {

/// Illumination Samples that never takes a subtree's samples at once: every leaf gets the whole list.
class WholeSampleLists final : public glossy::IlluminationSamples {
 public:
  bool reflectShared(hr::NodeId, std::span<const hr::IncidentSample>) override { return false; }
};

/// The extension's statistic of that name, -1 when it has none.
inline double statOf(const hr::Extension& e, const std::string& name) {
  for (const auto& s : e.stats())
    if (s.name == name) return s.value;
  return -1.0;
}

/// The layered run did use layers, and reflected fewer than half the samples the whole lists did.
inline void expectLayersTookMostSamples(const hr::Extension& layered, const hr::Extension& whole) {
  const double layers = statOf(layered, "reflect_shared_layers");
  const double a = statOf(layered, "samples_received_total"), b = statOf(whole, "samples_received_total");
  std::printf("layers %.0f; samples reflected %.0f layered, %.0f whole (%.2f)\n", layers, a, b, a / b);
  EXPECT_GT(layers, 0.0);
  EXPECT_LT(a, 0.5 * b);
}

}  // namespace testutil
