// Comparing two directional functions where it matters: the relative L1 distance over directions
// drawn half uniformly over the sphere and half within 0.3 rad of a direction of interest (where the
// lobes are), each weighted by the mixture's density, so that narrow lobes are seen.
#pragma once
#include <functional>
#include <random>

#include "directions.h"

namespace testdirs {

inline double relativeL1(const std::function<double(const glossy::Vec3&)>& got,
                         const std::function<double(const glossy::Vec3&)>& want, const glossy::Vec3& towards,
                         int count = 40000) {
  std::mt19937_64 g(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  glossy::Vec3 a, b;
  glossy::orthonormalBasis(towards, a, b);
  const double cosR = std::cos(0.3), cone = 2.0 * glossy::kPi * (1.0 - cosR);
  double diff = 0.0, norm = 0.0;
  for (int k = 0; k < count; ++k) {
    glossy::Vec3 d;
    if (k % 2) {
      d = sphere(g);
    } else {  // uniform in the cap: cos uniform in [cosR, 1]
      double z = 1.0 - u(g) * (1.0 - cosR), r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * glossy::kPi * u(g);
      d = z * towards + r * (std::cos(phi) * a + std::sin(phi) * b);
    }
    double pdf = 0.5 / (4.0 * glossy::kPi) + (glm::dot(d, towards) >= cosR ? 0.5 / cone : 0.0);
    double x = got(d), y = want(d);
    diff += std::abs(x - y) / pdf;
    norm += std::abs(y) / pdf;
  }
  return norm > 0.0 ? diff / norm : 0.0;
}

/// The largest relative difference over the three channels (powers, intensities).
inline double relDiff(const glossy::Rgb& a, const glossy::Rgb& b) {
  double w = 0.0;
  for (int c = 0; c < 3; ++c) w = std::max(w, std::abs(a[c] - b[c]) / std::max(std::abs(b[c]), 1e-300));
  return w;
}

}  // namespace testdirs
