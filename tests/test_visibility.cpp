// Embree's answers against a brute-force segment/triangle test (double precision, every patch).
#include <gtest/gtest.h>
#include <hr/rng.h>
#include <hr/visibility.h>

namespace {

/// Moeller-Trumbore over every triangle; segment ends trimmed like Visibility does.
bool bruteOccluded(const std::vector<hr::Patch>& ps, const hr::Vec3& a, const hr::Vec3& b, double eps) {
  hr::Vec3 d = b - a;
  double len = glm::length(d);
  double t0 = eps / len, t1 = 1.0 - eps / len;
  for (const auto& p : ps)
    for (int k = 1; k + 1 < p.poly.n; ++k) {
      hr::Vec3 v0 = p.poly.v[0], e1 = p.poly.v[k] - v0, e2 = p.poly.v[k + 1] - v0;
      hr::Vec3 pv = glm::cross(d, e2);
      double det = glm::dot(e1, pv);
      if (std::abs(det) < 1e-300) continue;
      hr::Vec3 tv = a - v0;
      double u = glm::dot(tv, pv) / det;
      if (u < 0 || u > 1) continue;
      hr::Vec3 qv = glm::cross(tv, e1);
      double v = glm::dot(d, qv) / det;
      if (v < 0 || u + v > 1) continue;
      double t = glm::dot(e2, qv) / det;
      if (t > t0 && t < t1) return true;
    }
  return false;
}

TEST(Visibility, EmbreeAgreesWithBruteForce) {
  hr::Scene sc = hr::defaultScene();
  hr::TessellationReport rep;
  auto patches = hr::buildPatches(sc, rep);
  hr::Visibility vis(patches);
  hr::Rng rng(7, 7);
  int disagree = 0, blocked = 0;
  const int N = 20000;
  std::vector<hr::Vec3> from(N), to(N);
  for (int i = 0; i < N; ++i) {
    for (int c = 0; c < 3; ++c) {
      from[i][c] = -0.2 + 2.4 * rng.uniform();
      to[i][c] = -0.2 + 2.4 * rng.uniform();
    }
  }
  std::vector<char> emb(N);
  bool b16[16];
  for (int i = 0; i < N; i += 16) {
    vis.occluded(&from[i], &to[i], 16, b16);
    for (int k = 0; k < 16; ++k) emb[i + k] = b16[k];
  }
  for (int i = 0; i < N; ++i) {
    bool ref = bruteOccluded(patches, from[i], to[i], vis.epsilon());
    blocked += ref;
    // Single-precision Embree may differ only for segments grazing an edge: allow 1 in 1000.
    disagree += ref != static_cast<bool>(emb[i]);
    EXPECT_EQ(vis.occluded(from[i], to[i]), static_cast<bool>(emb[i])) << "bundled and single rays agree";
  }
  EXPECT_GT(blocked, N / 10);
  EXPECT_LT(blocked, N - N / 10);
  EXPECT_LE(disagree, N / 1000) << disagree << " of " << N;
}

TEST(Visibility, PrimaryRaysHitTheRightPatch) {
  hr::Scene sc = hr::defaultScene();
  hr::TessellationReport rep;
  auto patches = hr::buildPatches(sc, rep);
  hr::Visibility vis(patches);
  // Straight down from above the light's centre onto the floor: the light is the first surface.
  auto hit = vis.intersect({1.0, 1.9, 1.0}, {0, -1, 0});
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(patches[hit.patch].object, 0u) << "floor is object 0";
  EXPECT_NEAR(hit.t, 1.9, 1e-4);
}

}  // namespace
