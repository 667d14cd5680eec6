// What accuracy costs for one reflected lobe: project the intensity a unit area of a material
// reflects from unit irradiance arriving from one direction, I(wo) = f(wi, wo) max(0, n.wo) (W/sr per
// W/m^2 per m^2), into a basis, and measure size, projection time, evaluation time and errors against
// the analytic lobe. Drives `glossyhr lobe`, the tests and the benchmark.
#pragma once
#include <glossy/brdf.h>
#include <glossy/distribution.h>

#include <cstdint>
#include <vector>

namespace glossy {

struct LobeSpec {
  double diffuse = 0.0, specular = 0.5, exponent = 100.0;
  double incidentDeg = 30.0;  // angle of wi from the normal (+z)
  double azimuthDeg = 0.0;    // azimuth of wi about the normal, from +x
  bool hints = true;          // Haar: refine around the mirror direction down to the lobe's width
  /// Project as a solve does (reflection.h: Haar by exact cell integrals, tetrahedron and spherical
  /// harmonics on a lobe widened to what they hold) and measure against the specular lobe alone (a
  /// solve's distributions hold rho_s only; the host keeps rho_d): what `--basis auto` is chosen by.
  bool asSolved = false;
  int errorDirections = 1 << 16;  // directions of the error estimates (fewer: faster, noisier)
};

struct LobeReport {
  std::size_t coefficients = 0, bytes = 0;
  double projectMs = 0.0, evalNs = 0.0;
  double l2RelError = 0.0;        // sqrt(int (P - I)^2 / int I^2), by importance sampling
  double maxRelError = 0.0;       // max |P - I| over the sampled directions, relative to I's peak
  double integralRelError = 0.0;  // |int P - int I| / int I, int I from the reference albedo
  double integral = 0.0, analyticIntegral = 0.0;  // W per (W/m^2 m^2), luminance of the RGB
};

/// The analytic lobe of a spec (grey: one value in all channels).
struct Lobe {
  ModifiedPhong brdf;
  Vec3 n{0, 0, 1}, wi;
  explicit Lobe(const LobeSpec& s);
  Lobe(const ModifiedPhong& b, const Vec3& incident) : brdf(b), wi(incident) {}
  Rgb operator()(const Vec3& wo) const { return eval(brdf, wi, wo, n) * std::max(0.0, glm::dot(n, wo)); }
  std::vector<PeakHint> hints() const;
};

/// Projects and measures. timing = false skips the repeated timing runs (tests).
LobeReport analyzeLobe(const LobeSpec& spec, const BasisSpec& basis, bool timing = true, AnyDistribution* out = nullptr);

}  // namespace glossy
