// The energy audit and display hooks: exitant samples average to the reflected power, stay in the
// leaf's hemisphere and have finite weights; Arvo's sampling is uniform over a spherical triangle
// and stays in it; clipping and projected solid angles match closed forms; the radiance a Haar leaf
// shows integrates back to its reflected power and matches f_s E at the mirror direction.
#include <glossy/brdf.h>
#include <glossy/spherical_geometry.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "fake_host.h"

namespace {

using glossy::FaceTri;
using glossy::Rgb;
using glossy::Vec3;
using glossy::kPi;
using testhost::NodeId;

TEST(IsGeometry, ClippedAreasAndProjectedSolidAngles) {
  FaceTri octant = glossy::octaRoot(0);
  Vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  auto p = glossy::SphericalPolygon::triangle(x, y, z);
  EXPECT_NEAR(p.area(), 0.5 * kPi, 1e-12);
  p.clip(glm::normalize(Vec3(1, -1, 0)));  // the half with x >= y
  EXPECT_NEAR(p.area(), 0.25 * kPi, 1e-12);
  p.clip(Vec3(0, 0, -1));  // keeps only the equator: nothing of positive area
  EXPECT_NEAR(p.area(), 0.0, 1e-12);
  EXPECT_NEAR(glossy::projectedSolidAngle(x, y, z, z), 0.25 * kPi, 1e-12) << "a quarter of pi";
  EXPECT_NEAR(glossy::projectedSolidAngle(z, y, x, z), 0.25 * kPi, 1e-12) << "either orientation";
  // The upper hemisphere's cells at level 4 project to pi in all.
  double sum = 0.0;
  auto visit = [&](auto&& self, const FaceTri& t, int level) -> void {
    if (level == 4) {
      sum += glossy::projectedSolidAngle(t.dir(0), t.dir(1), t.dir(2), z);
      return;
    }
    for (int k = 0; k < 4; ++k) self(self, t.child(k), level + 1);
  };
  for (int f = 0; f < 4; ++f) visit(visit, glossy::octaRoot(f), 0);
  EXPECT_NEAR(sum, kPi, 1e-9);
  (void)octant;
}

TEST(IsGeometry, TriangleSamplesAreUniformAndInside) {
  // Counts in the 16 grandchildren of the triangle against their solid angles: chi-square with 15
  // degrees of freedom below 37.7 (significance 0.001), for a root octant, a level-3 cell, a level-10
  // cell (0.09 degrees) and a sliver; every sample inside the triangle.
  std::mt19937_64 g(99);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  FaceTri deep = glossy::octaRoot(3);
  for (int k = 0; k < 10; ++k) deep = deep.child(k % 4);
  FaceTri sliver{{Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0.02)}};
  const FaceTri cases[] = {glossy::octaRoot(0), glossy::octaRoot(5).child(1).child(3).child(2), deep, sliver};
  for (const FaceTri& t : cases) {
    Vec3 a = t.dir(0), b = t.dir(1), c = t.dir(2), in[3];
    glossy::insideNormals(a, b, c, in);
    FaceTri sub[16];
    double expected[16], total = t.solidAngle();
    for (int i = 0; i < 16; ++i) {
      sub[i] = t.child(i / 4).child(i % 4);
      expected[i] = sub[i].solidAngle() / total;
    }
    const int N = 200000;
    int count[16] = {};
    for (int s = 0; s < N; ++s) {
      Vec3 d = glossy::sampleTriangle(a, b, c, u(g), u(g));
      ASSERT_NEAR(glm::length(d), 1.0, 1e-12);
      for (const Vec3& m : in) ASSERT_GE(glm::dot(d, m) / glm::length(m), -1e-12) << "inside";
      for (int i = 0; i < 16; ++i) {
        Vec3 m[3];
        glossy::insideNormals(sub[i].dir(0), sub[i].dir(1), sub[i].dir(2), m);
        if (glm::dot(d, m[0]) >= 0 && glm::dot(d, m[1]) >= 0 && glm::dot(d, m[2]) >= 0) {
          ++count[i];
          break;
        }
      }
    }
    double chi2 = 0.0;
    for (int i = 0; i < 16; ++i) chi2 += std::pow(count[i] - N * expected[i], 2) / (N * expected[i]);
    std::printf("Arvo sampling, triangle of %.3g sr: chi-square %.1f (15 dof)\n", total, chi2);
    EXPECT_LT(chi2, 37.7);
  }
}

TEST(IsEnergy, ExitantSamplesAverageToTheReflectedPower) {
  // Mean weight within 4 standard errors and 1 % of reflectedPower, directions in the leaf's
  // hemisphere, weights finite and non-negative; for each basis, on a floor leaf and the tilted leaf.
  for (const char* basis : {"haar", "tetra", "sh"}) {
    for (double n : {30.0, 1e4}) {
      testhost::Scene scene(n);
      auto ext = testhost::configured({{"basis", basis}});
      ext->attach(scene.host);
      for (NodeId leaf : {scene.floorLeaves[1], scene.tilted}) {
        Vec3 nrm = scene.host.info(leaf).normal;
        std::vector<hr::IncidentSample> s = {testhost::sample(testhost::around(nrm, 0.3, 1.0), Rgb(2.0, 1.0, 0.5)),
                                             testhost::sample(testhost::around(nrm, 1.2, 4.0), Rgb(0.5, 1.0, 2.0)),
                                             testhost::sample(testhost::around(nrm, 1.5, 2.0), Rgb(1.0))};
        ext->reflect(leaf, s);
        const Rgb power = ext->reflectedPower(leaf);
        // (u1, u2) on a jittered 512 x 256 grid: the estimate stays unbiased, with less variance
        // than independent draws (so the independent-draw standard error below is conservative).
        std::mt19937_64 g(12);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        const int N1 = 512, N2 = 256, N = N1 * N2;
        Rgb sum(0.0), sum2(0.0);
        for (int k = 0; k < N; ++k) {
          Vec3 d;
          Rgb w = ext->sampleExitant(leaf, (k / N2 + u(g)) / N1, (k % N2 + u(g)) / N2, d);
          ASSERT_TRUE(hr::allFinite(w) && hr::allFinite(d));
          ASSERT_NEAR(glm::length(d), 1.0, 1e-9);
          ASSERT_GE(glm::dot(d, nrm), -1e-12) << basis << ": in the leaf's hemisphere";
          ASSERT_GE(glm::min(w.x, glm::min(w.y, w.z)), 0.0);
          sum += w;
          sum2 += w * w;
        }
        Rgb mean = sum / double(N), se = glm::sqrt(glm::max(Rgb(0.0), sum2 / double(N) - mean * mean) / double(N));
        double worst = 0.0, worstSe = 0.0;
        for (int c = 0; c < 3; ++c) {
          EXPECT_LT(std::abs(mean[c] - power[c]), 4.0 * se[c] + 1e-12 * power[c]) << basis << " n " << n << " channel " << c;
          if (std::abs(mean[c] / power[c] - 1.0) >= worst) worst = std::abs(mean[c] / power[c] - 1.0), worstSe = se[c] / power[c];
        }
        EXPECT_LT(worst, 0.01) << basis << " n " << n;
        std::printf("%-5s n = %-5g leaf %u: sample mean / reflected power - 1 = %.1e (independent-draw standard error %.1e)\n",
                    basis, n, leaf.value, worst, worstSe);
      }
    }
  }
}

TEST(IsDisplay, HaarRadianceIntegratesToThePowerAndPeaksAtFsE) {
  // sum over the hemisphere of L A cos = reflected power (1 %, midpoint rule on 512 x 1024 cells);
  // at the mirror direction L = f_s E = rho_s (n + 2) / (2 pi) E (2 %, eps 0.02, levels to 8).
  testhost::Scene scene(100.0);
  auto ext = testhost::configured({{"dir-eps", "0.02"}, {"dir-max-level", "8"}});
  ext->attach(scene.host);
  NodeId leaf = scene.floorLeaves[2];
  const double A = scene.host.info(leaf).area;
  Vec3 wi = testhost::around(Vec3(0, 0, 1), 0.7, 0.4);
  const Rgb E(2.0, 1.0, 0.5);
  hr::IncidentSample s = testhost::sample(wi, E);
  ext->reflect(leaf, {&s, 1});
  const int NZ = 512, NP = 1024;
  Rgb sum(0.0);
  for (int i = 0; i < NZ; ++i) {
    double z = (i + 0.5) / NZ, r = std::sqrt(1.0 - z * z);
    for (int j = 0; j < NP; ++j) {
      double phi = 2.0 * kPi * (j + 0.5) / NP;
      sum += ext->radiance(leaf, Vec3(r * std::cos(phi), r * std::sin(phi), z)) * A * z;
    }
  }
  sum *= 2.0 * kPi / (NZ * NP);
  Rgb p = ext->reflectedPower(leaf);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c] / p[c], 1.0, 0.01) << c;
  Rgb peak = ext->radiance(leaf, glossy::mirror(wi, Vec3(0, 0, 1)));
  Rgb want = scene.host.materials[0].specular * (102.0 / (2.0 * kPi)) * E;
  std::printf("radiance: integral / power %.5f, at the mirror direction %.4f of f_s E\n", sum.x / p.x, peak.x / want.x);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(peak[c] / want[c], 1.0, 0.02) << c;
}

}  // namespace
