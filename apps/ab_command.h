// `glossyhr ab`: a scene solved diffuse-only and glossy, side by side (apps/ab_command.cpp).
#pragma once
#include <optional>
#include <string>

struct AbArgs {
  std::string scene, out = "out/ab", algorithm = "is";
  std::optional<double> eps;
  std::optional<int> threads;
  bool quiet = false;
};

int runAb(const AbArgs& a);
