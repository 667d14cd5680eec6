// Measuring a projected lobe. Errors use 2^16 directions drawn half uniformly over the sphere and
// half from the cos^n lobe around the mirror direction (a defensive mixture: uniform directions
// alone almost never land in a 1-degree lobe), weighted by the mixture's density.
#include <glossy/lobe.h>
#include <glossy/reflection.h>

#include <algorithm>
#include <chrono>
#include <random>

namespace glossy {

namespace {

using Clock = std::chrono::steady_clock;

/// Portable uniform [0, 1) from a 64-bit engine (the standard distributions differ between libraries).
double uniform(std::mt19937_64& g) { return double(g() >> 11) * 0x1.0p-53; }

struct AxisFrame {
  Vec3 u, v, w;
  explicit AxisFrame(const Vec3& z) : w(z) { orthonormalBasis(z, u, v); }
};

}  // namespace

Lobe::Lobe(const LobeSpec& s) {
  brdf.diffuse = Rgb(s.diffuse);
  brdf.specular = Rgb(s.specular);
  brdf.exponent = s.exponent;
  double t = s.incidentDeg * kPi / 180.0, a = s.azimuthDeg * kPi / 180.0;
  wi = Vec3(std::sin(t) * std::cos(a), std::sin(t) * std::sin(a), std::cos(t));
}

std::vector<PeakHint> Lobe::hints() const {
  if (hr::maxComponent(brdf.specular) <= 0.0) return {};
  return {PeakHint{mirror(wi, n), phongLobeWidth(brdf.exponent)}};
}

namespace {

/// The lobe of unit irradiance on unit area as a solve's reflection projects it (one sample).
AnyDistribution projectAsSolved(const Lobe& lobe, const BasisSpec& basis) {
  hr::IncidentSample s{lobe.wi, Rgb(1.0)};
  ReflectCounts counts;
  double n = representableExponent(basis, lobe.brdf.exponent);
  LobeSet set = makeLobes({&s, 1}, Frame::world(), lobe.n, 1.0, lobe.brdf.specular, n, 0.0, counts);
  return projectLobes(set, basis, counts);
}

}  // namespace

LobeReport analyzeLobe(const LobeSpec& spec, const BasisSpec& basis, bool timing, AnyDistribution* out) {
  LobeSpec reference = spec;
  if (spec.asSolved) reference.diffuse = 0.0;
  Lobe lobe(reference);
  std::vector<PeakHint> hints = spec.hints ? lobe.hints() : std::vector<PeakHint>{};
  LobeReport r;
  auto projectOnce = [&] { return spec.asSolved ? projectAsSolved(lobe, basis) : project(basis, lobe, hints); };

  auto t0 = Clock::now();
  AnyDistribution d = projectOnce();
  r.projectMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  if (timing) {
    // Best of several runs, at least 50 ms in all: single projections are too short to time.
    double total = r.projectMs;
    for (int k = 0; k < 20 && total < 50.0; ++k) {
      auto t1 = Clock::now();
      AnyDistribution again = projectOnce();
      double ms = std::chrono::duration<double, std::milli>(Clock::now() - t1).count();
      r.projectMs = std::min(r.projectMs, ms);
      total += ms;
    }
  }
  r.coefficients = coefficients(d);
  r.bytes = bytes(d);

  // Directions for the error estimates.
  const int N = std::max(spec.errorDirections, 2);
  std::mt19937_64 g(0x10BEull);
  Vec3 m = mirror(lobe.wi, lobe.n);
  AxisFrame f(m);
  const double n = spec.exponent;
  std::vector<Vec3> dirs(N);
  std::vector<double> pdf(N);
  for (int k = 0; k < N; ++k) {
    if (k % 2 == 0) {
      double z = 1.0 - 2.0 * uniform(g), a = 2.0 * kPi * uniform(g), s = std::sqrt(std::max(0.0, 1.0 - z * z));
      dirs[k] = Vec3(s * std::cos(a), s * std::sin(a), z);
    } else {
      double ca = std::pow(uniform(g), 1.0 / (n + 1.0)), sa = std::sqrt(std::max(0.0, 1.0 - ca * ca));
      double a = 2.0 * kPi * uniform(g);
      dirs[k] = ca * f.w + sa * (std::cos(a) * f.u + std::sin(a) * f.v);
    }
    double ca = glm::dot(dirs[k], m);
    double lobePdf = ca > 0.0 ? (n + 1.0) / (2.0 * kPi) * std::pow(ca, n) : 0.0;
    pdf[k] = 0.5 / (4.0 * kPi) + 0.5 * lobePdf;
  }
  double e2 = 0.0, f2 = 0.0, emax = 0.0;
  double peak = hr::luminance(lobe(m));
  for (int k = 0; k < N; ++k) {
    double a = hr::luminance(lobe(dirs[k])), p = hr::luminance(eval(d, dirs[k]));
    peak = std::max(peak, a);
    e2 += (p - a) * (p - a) / pdf[k];
    f2 += a * a / pdf[k];
    emax = std::max(emax, std::abs(p - a));
  }
  r.l2RelError = f2 > 0.0 ? std::sqrt(e2 / f2) : 0.0;
  r.maxRelError = peak > 0.0 ? emax / peak : 0.0;
  r.analyticIntegral = hr::luminance(albedo(lobe.brdf, lobe.wi, lobe.n));
  r.integral = hr::luminance(integral(d));
  r.integralRelError = r.analyticIntegral > 0.0 ? std::abs(r.integral - r.analyticIntegral) / r.analyticIntegral : 0.0;

  if (timing) {
    // Mean evaluation time over the same directions, best of three sweeps.
    double best = 1e30, sink = 0.0;
    for (int rep = 0; rep < 3; ++rep) {
      auto t1 = Clock::now();
      std::visit(
          [&](const auto& x) {
            for (const Vec3& v : dirs) sink += x.eval(v).x;
          },
          d);
      best = std::min(best, std::chrono::duration<double, std::nano>(Clock::now() - t1).count() / N);
    }
    r.evalNs = best + (sink == 12345.678 ? 1e-9 : 0.0);  // keeps the sweep from being optimised away
  }
  if (out) *out = std::move(d);
  return r;
}

}  // namespace glossy
