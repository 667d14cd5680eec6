// Reflection models behind one small interface: a variant of concrete models, each with eval (and a
// reference albedo). Directions point away from the surface: wi toward the light, wo toward the
// viewer, n the unit normal; f is 0 when either lies below the surface. Models join by adding a type.
#pragma once
#include <glossy/sphere.h>

#include <cmath>
#include <variant>

namespace glossy {

/// f = rho / pi.
struct Lambert {
  Rgb rho{0.0};
};

/// The modified Phong model (Lafortune and Willems 1994): f = rho_d / pi + rho_s (n + 2) / (2 pi)
/// cos^n(alpha), alpha between wo and the mirror direction of wi. Energy conserving and reciprocal;
/// albedo at normal incidence is exactly rho_d + rho_s.
struct ModifiedPhong {
  Rgb diffuse{0.0};
  Rgb specular{0.0};
  double exponent = 1.0;
};

using Brdf = std::variant<Lambert, ModifiedPhong>;

inline Vec3 mirror(const Vec3& wi, const Vec3& n) { return 2.0 * glm::dot(n, wi) * n - wi; }

inline Rgb eval(const Lambert& b, const Vec3& wi, const Vec3& wo, const Vec3& n) {
  return glm::dot(wi, n) > 0.0 && glm::dot(wo, n) > 0.0 ? b.rho / kPi : Rgb(0.0);
}

inline Rgb eval(const ModifiedPhong& b, const Vec3& wi, const Vec3& wo, const Vec3& n) {
  if (glm::dot(wi, n) <= 0.0 || glm::dot(wo, n) <= 0.0) return Rgb(0.0);
  // Symmetric in wi and wo (dot(mirror(wi), wo) = 2 (n.wi)(n.wo) - wi.wo), hence reciprocal.
  double c = glm::clamp(2.0 * glm::dot(n, wi) * glm::dot(n, wo) - glm::dot(wi, wo), 0.0, 1.0);
  double lobe = (b.exponent + 2.0) / (2.0 * kPi) * std::pow(c, b.exponent);
  return b.diffuse / kPi + b.specular * lobe;
}

inline Rgb eval(const Brdf& b, const Vec3& wi, const Vec3& wo, const Vec3& n) {
  return std::visit([&](const auto& m) { return eval(m, wi, wo, n); }, b);
}

/// A direction drawn for importance sampling, with its probability density (per steradian).
struct BrdfSample {
  Vec3 wo{0.0};
  double pdf = 0.0;
};

/// Samples wo for light from wi (u1..u3 uniform in [0, 1)): with probability rho_d / (rho_d + rho_s)
/// (luminances) a cosine-distributed direction about n, otherwise a cos^n lobe about the mirror
/// direction. A lobe sample may fall below the surface: f is then 0 and the path ends.
BrdfSample sample(const ModifiedPhong& b, const Vec3& wi, const Vec3& n, double u1, double u2, double u3);
/// The density sample() draws wo with, per steradian.
double pdf(const ModifiedPhong& b, const Vec3& wi, const Vec3& wo, const Vec3& n);

/// Directional albedo for light from wi: the integral of f cos(theta_o) over the hemisphere, by
/// quadrature in the lobe's frame with resolution x 2 resolution nodes; the reference the tests and
/// `glossyhr lobe` compare with (the default is accurate to about 1e-5 even for n = 1).
Rgb albedo(const Brdf& b, const Vec3& wi, const Vec3& n, int resolution = 512);

/// Half-angle (radians) at which a cos^n lobe falls to 1 % of its peak: the width of a peak hint.
inline double phongLobeWidth(double exponent) {
  if (exponent <= 0.0) return 0.5 * kPi;
  return std::min(0.5 * kPi, std::acos(std::pow(0.01, 1.0 / exponent)));
}

/// True when the model reflects any light directionally (is not plain Lambertian).
inline bool isGlossy(const Brdf& b) {
  const auto* p = std::get_if<ModifiedPhong>(&b);
  return p != nullptr && hr::maxComponent(p->specular) > 0.0;
}

}  // namespace glossy
