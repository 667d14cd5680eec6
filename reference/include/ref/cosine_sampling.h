// Cosine-weighted directions about a normal, for Lambertian vertices: density cos(theta) / pi, so
// that f cos / pdf is exactly rho and a diffuse bounce costs neither a pow nor a mixture choice.
#pragma once
#include <glossy/sphere.h>
#include <ref/sample_stream.h>

#include <cmath>

namespace ref {

/// Malley's method: a uniform point on the unit disk (concentric map, Shirley and Chiu 1997, which
/// keeps strata compact) lifted to the hemisphere about n; t and b complete n to an orthonormal frame.
inline hr::Vec3 sampleCosine(const hr::Vec3& n, const hr::Vec3& t, const hr::Vec3& b, Uv s) {
  double p = 2.0 * s.u - 1.0, q = 2.0 * s.v - 1.0;
  double r = 0.0, phi = 0.0;
  if (p != 0.0 || q != 0.0) {
    if (std::abs(p) > std::abs(q)) {
      r = p, phi = 0.25 * glossy::kPi * (q / p);
    } else {
      r = q, phi = 0.5 * glossy::kPi - 0.25 * glossy::kPi * (p / q);
    }
  }
  double x = r * std::cos(phi), y = r * std::sin(phi);
  double z = std::sqrt(std::max(0.0, 1.0 - x * x - y * y));
  return x * t + y * b + z * n;
}

inline double cosinePdf(const hr::Vec3& n, const hr::Vec3& w) {
  double c = glm::dot(n, w);
  return c > 0.0 ? c / glossy::kPi : 0.0;
}

}  // namespace ref
