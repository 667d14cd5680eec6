// Reference albedos. For the Phong lobe the quadrature runs in the lobe's own frame, with
// s = cos(alpha)^(n+1) as variable so that even n = 5000 is smooth in s; the horizon cut is the only
// kink, handled by many nodes in phi.
#include <glossy/brdf.h>


namespace glossy {

namespace {

/// Midpoint nodes: robust for the kink at the horizon.
double phongSpecularAlbedo(double exponent, const Vec3& wi, const Vec3& n, int resolution) {
  if (glm::dot(wi, n) <= 0.0) return 0.0;
  Vec3 r = mirror(wi, n);
  Vec3 t = std::abs(r.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  Vec3 u = glm::normalize(glm::cross(t, r)), v = glm::cross(r, u);
  const int NS = resolution, NP = 2 * resolution;
  double sum = 0.0;
  for (int i = 0; i < NS; ++i) {
    double s = (i + 0.5) / NS;
    double ca = std::pow(s, 1.0 / (exponent + 1.0));
    double sa = std::sqrt(std::max(0.0, 1.0 - ca * ca));
    for (int j = 0; j < NP; ++j) {
      double phi = 2.0 * kPi * (j + 0.5) / NP;
      Vec3 wo = ca * r + sa * (std::cos(phi) * u + std::sin(phi) * v);
      sum += std::max(0.0, glm::dot(wo, n));
    }
  }
  // integral of (n+2)/(2 pi) cos^n(alpha) cos(theta_o) d(cos alpha) d(phi), with
  // cos^n(alpha) d(cos alpha) = ds / (n + 1).
  return (exponent + 2.0) / (2.0 * kPi) / (exponent + 1.0) * (2.0 * kPi) * sum / (double(NS) * NP);
}

}  // namespace

Rgb albedo(const Brdf& b, const Vec3& wi, const Vec3& n, int resolution) {
  if (const auto* l = std::get_if<Lambert>(&b)) return glm::dot(wi, n) > 0.0 ? l->rho : Rgb(0.0);
  const auto& p = std::get<ModifiedPhong>(b);
  if (glm::dot(wi, n) <= 0.0) return Rgb(0.0);
  return p.diffuse + p.specular * phongSpecularAlbedo(p.exponent, wi, n, resolution);
}

}  // namespace glossy
