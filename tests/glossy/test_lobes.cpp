// Projected Phong lobes against the analytic lobe: sharp lobes are never missed with the default
// options (integral against the reference albedo), the adaptive basis beats the non-adaptive one on
// a sharp lobe (the paper's Table 1 finding), and the relative refiner's subdivision depends on the
// lobe's form only, not on its magnitude (§5.1).
#include <glossy/lobe.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <set>

#include "directions.h"

namespace {

using glossy::Rgb;
using glossy::Vec3;
using glossy::kPi;

struct SharpStats {
  double worst = 0.0, lowest = 1e9;
  std::size_t meanCoefficients = 0;
};

/// Integral of projected lobes over random incident directions, relative to the reference albedo.
SharpStats sharpLobes(double exponent, const glossy::HaarOptions& o, bool hints, const std::vector<Vec3>& wis,
                      const std::vector<double>& ref) {
  SharpStats s;
  glossy::ModifiedPhong b{Rgb(0.0), Rgb(1.0), exponent};
  std::size_t coef = 0;
  for (std::size_t k = 0; k < wis.size(); ++k) {
    glossy::Lobe lobe(b, wis[k]);
    auto h = hints ? lobe.hints() : std::vector<glossy::PeakHint>{};
    auto d = glossy::HaarDistribution::project(lobe, o, h);
    double r = d.integral().x / ref[k];
    s.worst = std::max(s.worst, std::abs(r - 1.0));
    s.lowest = std::min(s.lowest, r);
    coef += d.coefficients();
  }
  s.meanCoefficients = coef / wis.size();
  return s;
}

TEST(SharpLobes, NeverMissedWithTheDefaults) {
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> wis;
  for (int k = 0; k < 1000; ++k) wis.push_back(testdirs::withCos(u(g), g));
  for (double n : {1000.0, 5000.0}) {
    std::vector<double> ref;
    for (const Vec3& wi : wis) ref.push_back(glossy::albedo(glossy::ModifiedPhong{Rgb(0.0), Rgb(1.0), n}, wi, Vec3(0, 0, 1), 128).x);
    glossy::HaarOptions defaults;
    SharpStats s = sharpLobes(n, defaults, true, wis, ref);
    EXPECT_LT(s.worst, 0.02) << "n = " << n << ": integral within 2 % of the analytic one";
    EXPECT_GT(s.lowest, 0.5) << "n = " << n << ": no lobe missed";
    // What the minimum level and the peak hints each contribute (printed for the record).
    glossy::HaarOptions none = defaults;
    none.minLevel = 0;
    SharpStats bare = sharpLobes(n, none, false, wis, ref), minOnly = sharpLobes(n, defaults, false, wis, ref);
    glossy::HaarOptions four = defaults;
    four.minLevel = 4;
    SharpStats min4 = sharpLobes(n, four, false, wis, ref);
    std::printf("n = %g over %zu incident directions (integral / analytic):\n", n, wis.size());
    std::printf("  defaults (min level 2 + hints): worst error %.4f, lowest %.4f, %zu coefficients\n", s.worst, s.lowest, s.meanCoefficients);
    std::printf("  min level 2, no hints:          worst error %.4f, lowest %.4f, %zu coefficients\n", minOnly.worst, minOnly.lowest, minOnly.meanCoefficients);
    std::printf("  min level 0, no hints:          worst error %.4f, lowest %.4f, %zu coefficients\n", bare.worst, bare.lowest, bare.meanCoefficients);
    std::printf("  min level 4, no hints:          worst error %.4f, lowest %.4f, %zu coefficients\n", min4.worst, min4.lowest, min4.meanCoefficients);
  }
}

TEST(SharpLobes, HaarNeedsFewerCoefficientsThanTheTetrahedron) {
  // n = 1000 (half-width about 2 degrees) at 30 degrees incidence: Haar at eps 0.2, max level 7
  // against the tetrahedron; error is the relative L2 error over importance-sampled directions.
  glossy::LobeSpec spec;
  spec.exponent = 1000.0;
  spec.specular = 0.8;
  spec.diffuse = 0.1;
  glossy::BasisSpec haar;
  haar.haar.eps = 0.2;
  haar.haar.maxLevel = 7;
  auto h = glossy::analyzeLobe(spec, haar, false);
  glossy::BasisSpec tetra;
  tetra.basis = glossy::Basis::Tetra;
  tetra.tetraLevel = 6;
  auto t6 = glossy::analyzeLobe(spec, tetra, false);
  std::printf("haar: %zu coefficients, l2 %.3f; tetra level 6: %zu coefficients, l2 %.3f\n", h.coefficients, h.l2RelError,
              t6.coefficients, t6.l2RelError);
  EXPECT_LT(h.l2RelError, 0.12);
  EXPECT_LT(h.coefficients * 4, t6.coefficients) << "a quarter of the coefficients...";
  EXPECT_GT(t6.l2RelError, 2.0 * h.l2RelError) << "... and less than half the error";
}

std::set<std::uint64_t> cells(const glossy::HaarDistribution& d) {
  std::set<std::uint64_t> s;
  d.visitLeaves([&](const glossy::FaceTri&, int, const Rgb&, std::uint64_t key) { s.insert(key); });
  return s;
}

double jaccard(const std::set<std::uint64_t>& a, const std::set<std::uint64_t>& b) {
  std::size_t common = 0;
  for (auto k : a) common += b.count(k);
  return double(common) / double(a.size() + b.size() - common);
}

TEST(Refiners, RelativeSubdivisionFollowsTheFormNotTheMagnitude) {
  // Neighbouring elements of a glossy floor: the lobe rotates 0.5 degrees from one to the next
  // while its magnitude falls 100x over 21 neighbours (25 % per step, as towards the edge of a
  // light's reach). The absolute threshold is calibrated to give the relative refiner's coefficient
  // count at the middle element. Similarity of neighbours' subdivisions = Jaccard index of their
  // leaf cells.
  glossy::ModifiedPhong b{Rgb(0.1), Rgb(0.8), 200.0};
  const int K = 21;
  auto lobeAt = [&](int k) {
    double t = (20.0 + 0.5 * k) * kPi / 180.0;
    return glossy::Lobe(b, Vec3(std::sin(t), 0.0, std::cos(t)));
  };
  auto scaleAt = [&](int k) { return 10.0 * std::pow(0.01, k / double(K - 1)); };
  auto projectAt = [&](int k, const glossy::HaarOptions& o) {
    glossy::Lobe lobe = lobeAt(k);
    double s = scaleAt(k);
    return glossy::HaarDistribution::project([&](const Vec3& d) { return s * lobe(d); }, o, lobe.hints());
  };
  glossy::HaarOptions rel;
  rel.maxLevel = 7;
  glossy::HaarOptions abs = rel;
  abs.refiner = glossy::Refiner::Absolute;
  std::size_t target = projectAt(K / 2, rel).coefficients();
  double lo = 1e-6, hi = 10.0;
  for (int it = 0; it < 60; ++it) {
    abs.eps = std::sqrt(lo * hi);
    (projectAt(K / 2, abs).coefficients() > target ? lo : hi) = abs.eps;
  }
  abs.eps = hi;
  auto similarity = [&](const glossy::HaarOptions& o, double& minimum) {
    double sum = 0.0;
    minimum = 1.0;
    auto prev = cells(projectAt(0, o));
    for (int k = 1; k < K; ++k) {
      auto cur = cells(projectAt(k, o));
      double j = jaccard(prev, cur);
      sum += j;
      minimum = std::min(minimum, j);
      prev = std::move(cur);
    }
    return sum / (K - 1);
  };
  double relMin = 0.0, absMin = 0.0;
  double relMean = similarity(rel, relMin), absMean = similarity(abs, absMin);
  std::printf("neighbour similarity (Jaccard): relative mean %.3f min %.3f; absolute (eps %.4g) mean %.3f min %.3f\n",
              relMean, relMin, abs.eps, absMean, absMin);
  EXPECT_GT(relMin, 0.8);
  EXPECT_LT(absMin, relMin - 0.15) << "the absolute refiner's subdivision jumps between neighbours";

  // The reason, exactly: scaling a function leaves the relative refiner's tree unchanged.
  glossy::Lobe lobe = lobeAt(0);
  auto scaled = [&](double s, const glossy::HaarOptions& o) {
    return cells(glossy::HaarDistribution::project([&](const Vec3& d) { return s * lobe(d); }, o, lobe.hints()));
  };
  EXPECT_EQ(jaccard(scaled(1.0 / 16.0, rel), scaled(16.0, rel)), 1.0);
  EXPECT_LT(jaccard(scaled(1.0 / 16.0, abs), scaled(16.0, abs)), 0.5);
}

}  // namespace
