// Cosine-weighted directions about a normal, for Lambertian vertices: density cos(theta) / pi, so
// that f cos / pdf is exactly rho and a diffuse bounce costs neither a pow nor a mixture choice.
#pragma once
#include <glossy/sphere.h>
#include <ref/sample_stream.h>

#include <cmath>

namespace ref {

/// Malley's method: a uniform point on the unit disk (concentric map, Shirley and Chiu 1997, which
/// keeps strata compact) lifted to the hemisphere about n.
inline hr::Vec3 sampleCosine(const hr::Vec3& n, Uv s) {
  double a = 2.0 * s.u - 1.0, b = 2.0 * s.v - 1.0;
  double r = 0.0, phi = 0.0;
  if (a != 0.0 || b != 0.0) {
    if (std::abs(a) > std::abs(b)) {
      r = a, phi = 0.25 * glossy::kPi * (b / a);
    } else {
      r = b, phi = 0.5 * glossy::kPi - 0.25 * glossy::kPi * (a / b);
    }
  }
  double x = r * std::cos(phi), y = r * std::sin(phi);
  double z = std::sqrt(std::max(0.0, 1.0 - x * x - y * y));
  hr::Vec3 t, bt;
  glossy::orthonormalBasis(n, t, bt);
  return x * t + y * bt + z * n;
}

inline double cosinePdf(const hr::Vec3& n, const hr::Vec3& w) {
  double c = glm::dot(n, w);
  return c > 0.0 ? c / glossy::kPi : 0.0;
}

}  // namespace ref
