// The path tracer's own sampling routines against the densities the estimator divides by: cosine
// directions against cos/pi, the emitter alias table against its weights (chi-square tests at
// significance 0.01), and the Sobol sample streams: each prefix of 2^m points of a stream is a
// (0,m,2)-net, and a point's randomisation is uniform over scrambles (chi-square).
#include <gtest/gtest.h>
#include <ref/alias_table.h>
#include <ref/cosine_sampling.h>
#include <ref/sample_stream.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

using hr::Vec3;

/// Upper tail probability of a chi-square statistic with k degrees of freedom by the Wilson-Hilferty
/// cube-root normal approximation (accurate to a few per cent of p for k >= 30, ample at 0.01).
double chiSquareP(double chi2, int k) {
  double h = 2.0 / (9.0 * k);
  double z = (std::cbrt(chi2 / k) - (1.0 - h)) / std::sqrt(h);
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

double chiSquare(const std::vector<double>& observed, const std::vector<double>& expected) {
  double c = 0.0;
  for (std::size_t i = 0; i < observed.size(); ++i)
    c += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
  return c;
}

TEST(ReferenceSampling, ChiSquareWilsonHilfertyMatchesTables) {
  EXPECT_NEAR(chiSquareP(67.505, 50), 0.05, 0.002);   // table: chi2(0.05, 50 dof)
  EXPECT_NEAR(chiSquareP(310.457, 255), 0.01, 0.001);  // chi2(0.01, 255 dof)
}

TEST(ReferenceSampling, CosineDirectionsFollowCosOverPi) {
  // Under cos/pi, 1 - cos^2(theta) and phi are independent and uniform: 16 x 16 equally likely bins.
  const Vec3 n = glm::normalize(Vec3(0.3, -0.5, 0.8));
  Vec3 t, b;
  glossy::orthonormalBasis(n, t, b);
  const int K = 16, N = 1000000;
  std::vector<double> observed(K * K, 0.0), expected(K * K, double(N) / (K * K));
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < N; ++k) {
    Vec3 w = ref::sampleCosine(n, t, b, {u(g), u(g)});
    ASSERT_NEAR(glm::length(w), 1.0, 1e-12);
    double c = glm::dot(w, n);
    ASSERT_GT(c, 0.0);
    double phi = std::atan2(glm::dot(w, b), glm::dot(w, t)) + glossy::kPi;
    int i = std::min(K - 1, int((1.0 - c * c) * K)), j = std::min(K - 1, int(phi / (2.0 * glossy::kPi) * K));
    observed[std::size_t(i * K + j)] += 1.0;
  }
  double chi2 = chiSquare(observed, expected), p = chiSquareP(chi2, K * K - 1);
  std::printf("cosine sampling: chi2 %.1f, %d degrees of freedom, p = %.3f\n", chi2, K * K - 1, p);
  EXPECT_GT(p, 0.01);
  EXPECT_NEAR(ref::cosinePdf(n, n), 1.0 / glossy::kPi, 1e-15);
  EXPECT_EQ(ref::cosinePdf(n, -n), 0.0);
}

TEST(ReferenceSampling, AliasTableDrawsInProportionToTheWeights) {
  const std::vector<double> w = {0.5, 3.0, 0.0, 1.0, 7.25, 2.0, 0.01, 0.0, 4.0, 1.5, 0.2, 9.0};
  ref::AliasTable table(w);
  double total = 0.0;
  for (double x : w) total += x;
  const int N = 2000000;
  std::vector<double> observed(w.size(), 0.0), expected;
  std::mt19937_64 g(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < N; ++k) observed[table.sample(u(g))] += 1.0;
  std::vector<double> obs;
  for (std::size_t i = 0; i < w.size(); ++i) {
    EXPECT_NEAR(table.pmf(std::uint32_t(i)), w[i] / total, 1e-15);
    if (w[i] == 0.0) {
      EXPECT_EQ(observed[i], 0.0) << "a weightless entry is never drawn";
      continue;
    }
    obs.push_back(observed[i]);
    expected.push_back(N * w[i] / total);
  }
  // Few categories: the exact tail Q(k/2, chi2/2) is not needed, a stricter bound suffices: the
  // 0.001 quantile of chi2 with 9 degrees of freedom is 27.88.
  double chi2 = chiSquare(obs, expected);
  std::printf("alias table: chi2 %.2f, %zu degrees of freedom\n", chi2, obs.size() - 1);
  ASSERT_EQ(obs.size(), 10u);
  EXPECT_LT(chi2, 27.88);
  EXPECT_EQ(table.sample(0.0), table.sample(0.0));
  EXPECT_LT(table.sample(std::nextafter(1.0, 0.0)), w.size());
  EXPECT_THROW(ref::AliasTable({0.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(ref::AliasTable({1.0, -1.0}), std::invalid_argument);
}

TEST(ReferenceSampling, SobolStreamPrefixesAreNets) {
  // Points 0 .. 2^m - 1 of one replicate (sample indices r, r + kReplicates, ...) in the camera's
  // dimension pair and in a deeper one: every elementary interval of area 2^-m holds one point.
  for (int dims : {1, 5})
    for (int m = 1; m <= 8; ++m) {
      const int n = 1 << m;
      std::vector<ref::Uv> pts;
      for (int j = 0; j < n; ++j) {
        ref::SampleStream s(42, 1234, std::uint64_t(j) * ref::kReplicates + 3);
        ref::Uv uv;
        for (int d = 0; d < dims; ++d) uv = s.get2D();
        pts.push_back(uv);
      }
      for (int a = 0; a <= m; ++a) {
        const int nx = 1 << a, ny = 1 << (m - a);
        std::vector<int> count(std::size_t(n), 0);
        for (const ref::Uv& p : pts) ++count[std::size_t(int(p.u * nx) * ny + int(p.v * ny))];
        for (int c : count) ASSERT_EQ(c, 1) << "m = " << m << ", intervals " << nx << " x " << ny << ", pair " << dims;
      }
    }
}

TEST(ReferenceSampling, SobolPointsAreUniformOverScrambles) {
  // One point (index 5 of replicate 2) in the third dimension pair and in a 1D dimension, over 10^5
  // pixels: each scramble is random, so the point is uniform on the square and on the line.
  const int K = 16, N = 100000;
  std::vector<double> o2(K * K, 0.0), e2(K * K, double(N) / (K * K)), o1(64, 0.0), e1(64, double(N) / 64);
  for (int px = 0; px < N; ++px) {
    ref::SampleStream s(9, std::uint64_t(px), 5 * ref::kReplicates + 2);
    s.get2D(), s.get2D();
    ref::Uv uv = s.get2D();
    double x = s.get1D();
    ASSERT_TRUE(uv.u >= 0.0 && uv.u < 1.0 && uv.v >= 0.0 && uv.v < 1.0 && x >= 0.0 && x < 1.0);
    o2[std::size_t(int(uv.u * K) * K + int(uv.v * K))] += 1.0;
    o1[std::size_t(x * 64)] += 1.0;
  }
  double c2 = chiSquare(o2, e2), c1 = chiSquare(o1, e1);
  std::printf("Sobol over scrambles: 2D chi2 %.1f (255 dof) p = %.3f, 1D chi2 %.1f (63 dof) p = %.3f\n", c2,
              chiSquareP(c2, 255), c1, chiSquareP(c1, 63));
  EXPECT_GT(chiSquareP(c2, K * K - 1), 0.01);
  EXPECT_GT(chiSquareP(c1, 63), 0.01);
}

}  // namespace
