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
  Vec3 u, v;
  orthonormalBasis(r, u, v);
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

namespace {

double diffuseShare(const ModifiedPhong& b) {
  double d = hr::luminance(b.diffuse), s = hr::luminance(b.specular);
  return d + s > 0.0 ? d / (d + s) : 1.0;
}

}  // namespace

BrdfSample sample(const ModifiedPhong& b, const Vec3& wi, const Vec3& n, double u1, double u2, double u3) {
  Vec3 axis = u1 < diffuseShare(b) ? n : mirror(wi, n);
  Vec3 u, v;
  orthonormalBasis(axis, u, v);
  double c = axis == n ? std::sqrt(u2) : std::pow(u2, 1.0 / (b.exponent + 1.0));
  double s = std::sqrt(std::max(0.0, 1.0 - c * c)), phi = 2.0 * kPi * u3;
  BrdfSample r;
  r.wo = c * axis + s * (std::cos(phi) * u + std::sin(phi) * v);
  r.pdf = pdf(b, wi, r.wo, n);
  return r;
}

double pdf(const ModifiedPhong& b, const Vec3& wi, const Vec3& wo, const Vec3& n) {
  double pd = diffuseShare(b);
  double cd = glm::dot(wo, n);
  double p = cd > 0.0 ? pd * cd / kPi : 0.0;
  double ca = glm::dot(wo, mirror(wi, n));
  if (ca > 0.0 && pd < 1.0) p += (1.0 - pd) * (b.exponent + 1.0) / (2.0 * kPi) * std::pow(ca, b.exponent);
  return p;
}

Rgb albedo(const Brdf& b, const Vec3& wi, const Vec3& n, int resolution) {
  if (const auto* l = std::get_if<Lambert>(&b)) return glm::dot(wi, n) > 0.0 ? l->rho : Rgb(0.0);
  const auto& p = std::get<ModifiedPhong>(b);
  if (glm::dot(wi, n) <= 0.0) return Rgb(0.0);
  return p.diffuse + p.specular * phongSpecularAlbedo(p.exponent, wi, n, resolution);
}

}  // namespace glossy
