// Importance sampling of the modified Phong model against its own density: a chi-square test of 10^6
// samples in bins of the mirror direction's frame (edges dense near the mirror so that even a
// 2-degree lobe spans several bins), expected counts by integrating pdf() over each bin. Passes at
// significance 0.01.
#include <glossy/brdf.h>
#include <gtest/gtest.h>

#include <random>

namespace {

using glossy::Vec3;
using glossy::kPi;

/// Regularised upper incomplete gamma Q(a, x): series below a + 1, continued fraction above.
double gammaQ(double a, double x) {
  if (x <= 0.0) return 1.0;
  double lg = std::lgamma(a);
  if (x < a + 1.0) {
    double sum = 1.0 / a, term = sum;
    for (int n = 1; n < 10000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < 1e-15 * std::abs(sum)) break;
    }
    return 1.0 - sum * std::exp(-x + a * std::log(x) - lg);
  }
  double b = x + 1.0 - a, c = 1e300, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::abs(c) < 1e-300) c = 1e-300;
    d = 1.0 / d;
    double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - lg) * h;
}

struct Bins {
  static constexpr int kAlpha = 24, kPhi = 16;
  Vec3 axis, u, v;
  double edge(int k) const { return kPi * std::pow(double(k) / kAlpha, 3.0); }
  int index(const Vec3& w) const {
    double a = std::acos(glm::clamp(glm::dot(w, axis), -1.0, 1.0));
    int ka = std::min(kAlpha - 1, static_cast<int>(std::cbrt(a / kPi) * kAlpha));
    while (ka > 0 && a < edge(ka)) --ka;
    while (ka < kAlpha - 1 && a >= edge(ka + 1)) ++ka;
    double phi = std::atan2(glm::dot(w, v), glm::dot(w, u));
    if (phi < 0.0) phi += 2.0 * kPi;
    int kp = std::min(kPhi - 1, static_cast<int>(phi / (2.0 * kPi) * kPhi));
    return ka * kPhi + kp;
  }
};

void chiSquare(double exponent) {
  const Vec3 n(0, 0, 1);
  const Vec3 wi = glm::normalize(Vec3(0.6, 0.2, 0.75));
  glossy::ModifiedPhong b{glossy::Rgb(0.3), glossy::Rgb(0.6), exponent};
  Bins bins;
  bins.axis = glossy::mirror(wi, n);
  glossy::orthonormalBasis(bins.axis, bins.u, bins.v);
  const int kBins = Bins::kAlpha * Bins::kPhi;
  // Expected probabilities: the pdf integrated over each bin on a 24 x 24 midpoint grid in
  // (alpha, phi), d(omega) = sin(alpha) d(alpha) d(phi).
  std::vector<double> expect(kBins, 0.0);
  double total = 0.0;
  for (int ka = 0; ka < Bins::kAlpha; ++ka)
    for (int kp = 0; kp < Bins::kPhi; ++kp) {
      double a0 = bins.edge(ka), a1 = bins.edge(ka + 1);
      const int G = 24;
      double sum = 0.0;
      for (int i = 0; i < G; ++i)
        for (int j = 0; j < G; ++j) {
          double a = a0 + (i + 0.5) / G * (a1 - a0);
          double phi = 2.0 * kPi * (kp + (j + 0.5) / G) / Bins::kPhi;
          Vec3 w = std::cos(a) * bins.axis + std::sin(a) * (std::cos(phi) * bins.u + std::sin(phi) * bins.v);
          sum += glossy::pdf(b, wi, w, n) * std::sin(a);
        }
      double p = sum * (a1 - a0) / G * (2.0 * kPi / Bins::kPhi) / G;
      expect[std::size_t(ka * Bins::kPhi + kp)] = p;
      total += p;
    }
  EXPECT_NEAR(total, 1.0, 2e-3) << "the density integrates to one (n = " << exponent << ")";
  const int N = 1000000;
  std::vector<double> observed(kBins, 0.0);
  std::mt19937_64 g(42);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < N; ++k) {
    glossy::BrdfSample s = glossy::sample(b, wi, n, u(g), u(g), u(g));
    ASSERT_NEAR(glm::length(s.wo), 1.0, 1e-9);
    ASSERT_GT(s.pdf, 0.0);
    observed[std::size_t(bins.index(s.wo))] += 1.0;
  }
  // Pool bins expected to hold fewer than 5 samples, then the usual statistic.
  double chi2 = 0.0, pooledE = 0.0, pooledO = 0.0;
  int dof = -1;
  for (int i = 0; i < kBins; ++i) {
    double e = expect[std::size_t(i)] * N;
    if (e < 5.0) {
      pooledE += e, pooledO += observed[std::size_t(i)];
      continue;
    }
    chi2 += (observed[std::size_t(i)] - e) * (observed[std::size_t(i)] - e) / e;
    ++dof;
  }
  if (pooledE >= 5.0) {
    chi2 += (pooledO - pooledE) * (pooledO - pooledE) / pooledE;
    ++dof;
  }
  double p = gammaQ(0.5 * dof, 0.5 * chi2);
  std::printf("n = %g: chi2 %.1f, %d degrees of freedom, p = %.3f\n", exponent, chi2, dof, p);
  EXPECT_GT(dof, 50) << "the bins resolve the lobe";
  EXPECT_GT(p, 0.01) << "n = " << exponent;
}

TEST(PhongSampling, ChiSquareExponent1) { chiSquare(1.0); }
TEST(PhongSampling, ChiSquareExponent10) { chiSquare(10.0); }
TEST(PhongSampling, ChiSquareExponent100) { chiSquare(100.0); }
TEST(PhongSampling, ChiSquareExponent1000) { chiSquare(1000.0); }

TEST(PhongSampling, GammaQMatchesKnownValues) {
  // Q(1, x) = exp(-x); Q(k/2, chi2/2) for the table value chi2(0.05, 10 dof) = 18.307.
  EXPECT_NEAR(gammaQ(1.0, 2.0), std::exp(-2.0), 1e-12);
  EXPECT_NEAR(gammaQ(5.0, 18.307 / 2.0), 0.05, 1e-4);
}

}  // namespace
