// Random directions for the glossy tests: a direction with a given cos(theta) and uniform azimuth.
#pragma once
#include <glossy/sphere.h>

#include <random>

namespace testdirs {

inline glossy::Vec3 withCos(double z, std::mt19937_64& g) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double a = 2.0 * glossy::kPi * u(g), s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {s * std::cos(a), s * std::sin(a), z};
}

/// Uniform over the sphere.
inline glossy::Vec3 sphere(std::mt19937_64& g) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return withCos(1.0 - 2.0 * u(g), g);
}

}  // namespace testdirs
