// Shooting with Illumination Samples (paper §3.4): reflectShot adds a pass's reflection to both the
// total and the unshot light (their power is the sum of the passes', exactly up to float rounding),
// shot() clears a subtree's unshot light and nothing else at the leaves, the pull sums unshot light as
// it sums the total (and once shooting, only the unshot light above the leaves) and leaves a node
// alone when none of its children changed, and a split hands the unshot light down with the total.
#include <glossy/is_options.h>
#include <gtest/gtest.h>

#include <random>

#include "compare.h"
#include "directions.h"
#include "fake_host.h"
#include "../saved_bytes.h"

namespace {

using glossy::Rgb;
using glossy::Vec3;
using glossy::kPi;
using testhost::NodeId;

using testdirs::relDiff;

std::vector<hr::IncidentSample> someSamples(const Vec3& n, unsigned seed, int count = 4) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<hr::IncidentSample> s;
  for (int k = 0; k < count; ++k)
    s.push_back(testhost::sample(testhost::around(n, 0.2 + 1.2 * u(g), 2.0 * kPi * u(g)), Rgb(1.0 + u(g), u(g), 0.5)));
  return s;
}

/// The power one gathering reflect of these samples gives a leaf (a fresh extension: no merging across calls).
Rgb reflectedAlone(const testhost::Scene& scene, NodeId leaf, const std::vector<hr::IncidentSample>& s, const char* basis) {
  auto ext = testhost::configured({{"basis", basis}});
  ext->attach(scene.host);
  ext->reflect(leaf, s);
  return ext->light(leaf)->power;
}

Rgb unshotOf(const hr::Extension& ext, NodeId n) { return ext.unshotPower(n); }

TEST(IsShooting, PassesAddToTotalAndUnshotAndShotClearsOnlyTheUnshot) {
  for (const char* basis : {"haar", "tetra", "sh"}) {
    testhost::Scene scene;
    auto ext = testhost::configured({{"basis", basis}});
    ext->attach(scene.host);
    EXPECT_TRUE(ext->canShoot());
    const NodeId leaf = scene.wall;
    const Vec3 n = scene.host.info(leaf).normal;
    auto s1 = someSamples(n, 1), s2 = someSamples(n, 2), s3 = someSamples(n, 3);
    const Rgb p1 = reflectedAlone(scene, leaf, s1, basis), p2 = reflectedAlone(scene, leaf, s2, basis),
              p3 = reflectedAlone(scene, leaf, s3, basis);
    ext->reflectShot(leaf, s1);
    EXPECT_LT(relDiff(ext->light(leaf)->power, p1), 1e-6) << basis;
    EXPECT_LT(relDiff(unshotOf(*ext, leaf), p1), 1e-6) << basis;
    for (const Vec3& d : {n, Vec3(0.6, 0.8, 0.0), Vec3(0.6, 0.0, 0.8)})
      EXPECT_EQ(ext->unshotIntensity(leaf, d), ext->intensity(leaf, d)) << basis;
    ext->reflectShot(leaf, s2);
    // Float rounding of the re-projected sums (Haar) and of the coefficient sums: 1e-6.
    EXPECT_LT(relDiff(ext->light(leaf)->power, p1 + p2), 1e-6) << basis;
    EXPECT_LT(relDiff(unshotOf(*ext, leaf), p1 + p2), 1e-6) << basis;
    const Rgb before = ext->light(leaf)->power;
    ext->shot(leaf);
    EXPECT_EQ(unshotOf(*ext, leaf), Rgb(0.0)) << basis;
    EXPECT_EQ(ext->unshotIntensity(leaf, n), Rgb(0.0)) << basis;
    EXPECT_EQ(ext->unshotIntensityBound(leaf, n, -1.0), Rgb(0.0)) << basis;
    EXPECT_EQ(ext->light(leaf)->power, before) << basis;
    ext->reflectShot(leaf, s3);
    EXPECT_LT(relDiff(unshotOf(*ext, leaf), p3), 1e-6) << basis;
    EXPECT_LT(relDiff(ext->light(leaf)->power, p1 + p2 + p3), 1e-6) << basis;
  }
}

TEST(IsShooting, CurvedLeafShowsItsSummedPassesAsAFlatOneDoes) {
  // A leaf of a curved surface (planar false, as the VISION-like host reports a sphere's leaves)
  // reflects about its one mean normal, as a flat leaf does; after two passes its light is a sum, and
  // that sum must keep the leaf's horizon, or radiance() (which divides by the cosine to it) shows
  // nothing: the shiny sphere of scenes/floor_gloss.json looked diffuse. Both leaves run the same
  // arithmetic, so their radiance toward every direction must agree exactly, and toward the mirror
  // directions of the samples it must be positive (the lobes are there).
  for (const char* basis : {"haar", "tetra", "sh"}) {
    testhost::Scene flat, curved;
    curved.host.node(curved.wall).info.planar = false;
    auto ef = testhost::configured({{"basis", basis}}), ec = testhost::configured({{"basis", basis}});
    ef->attach(flat.host);
    ec->attach(curved.host);
    const Vec3 n = flat.host.info(flat.wall).normal;
    const auto s1 = someSamples(n, 7), s2 = someSamples(n, 8);
    for (const auto* s : {&s1, &s2}) ef->reflectShot(flat.wall, *s), ec->reflectShot(curved.wall, *s);
    double brightest = 0.0;
    for (const auto* s : {&s1, &s2})
      for (const hr::IncidentSample& x : *s) {
        const Vec3 out = 2.0 * glm::dot(n, x.toSender) * n - x.toSender;
        const Rgb Lf = ef->radiance(flat.wall, out), Lc = ec->radiance(curved.wall, out);
        EXPECT_EQ(Lc, Lf) << basis << ": curved leaf toward a mirror direction";
        brightest = std::max(brightest, Lf.x);
      }
    EXPECT_GT(brightest, 0.0) << basis;
  }
}

TEST(IsShooting, CurvedLeafSplitIntoTiltedChildrenSavesAndLoadsInTheirFrames) {
  // A curved leaf split into children that face up to 8 degrees away from it (a sphere's leaf, or
  // its display cells): each child's light must live in its own frame under its own horizon, since a
  // solution file restores every flat cell in the frame of its own normal. Saved and loaded, every
  // child must evaluate exactly as before (same data, same frame), and the load must not refuse light
  // below a child's horizon (which a pass summed into a tilted child left there).
  for (const char* basis : {"haar", "tetra", "sh"}) {
    testhost::Scene sc;
    testhost::FakeHost& h = sc.host;
    h.node(sc.wall).info.planar = false;
    auto ext = testhost::configured({{"basis", basis}});
    ext->attach(h);
    const Vec3 n = h.info(sc.wall).normal;
    ext->reflectShot(sc.wall, someSamples(n, 11));
    std::vector<NodeId> kids = h.split(sc.wall);
    const double tilt[4] = {0.0, 0.05, 0.1, 0.14};  // rad, about z and y in turn
    for (int k = 0; k < 4; ++k) {
      hr::NodeInfo& ci = h.node(kids[std::size_t(k)]).info;
      ci.planar = false;
      ci.normal = glm::normalize(n + tilt[k] * (k % 2 ? Vec3(0, 1, 0) : Vec3(0, 0, 1)));
    }
    ext->attach(h);
    ext->split(sc.wall, kids);
    ext->reflectShot(kids[2], someSamples(h.info(kids[2]).normal, 12));
    testhost::FakeHost flat = h.elementsOnly();
    for (NodeId c : kids) flat.node(c).info.planar = true;  // a solution's cells are flat
    glossy::IlluminationSamples loaded;
    ASSERT_NO_THROW(loaded.load(testutil::savedBytes(*ext), flat)) << basis;
    double brightest = 0.0;
    for (NodeId c : kids)
      for (int k = 0; k < 64; ++k) {
        const Vec3 d = testhost::around(h.info(c).normal, 1.4 * (k % 8) / 8.0, 2.0 * kPi * (k / 8) / 8.0);
        EXPECT_EQ(loaded.radiance(c, d), ext->radiance(c, d)) << basis << ", child " << c.index();
        brightest = std::max(brightest, ext->radiance(c, d).x);
      }
    EXPECT_GT(brightest, 0.0) << basis;
  }
}

TEST(IsShooting, UnshotBoundCoversTheUnshotIntensityInItsCone) {
  testhost::Scene scene;
  auto ext = testhost::configured();
  ext->attach(scene.host);
  ext->reflectShot(scene.wall, someSamples(scene.host.info(scene.wall).normal, 4, 12));
  std::mt19937_64 g(5);
  for (int k = 0; k < 300; ++k) {
    Vec3 axis = testdirs::sphere(g), d = testdirs::sphere(g);
    double cosHalf = std::cos(0.05 + 1.5 * std::uniform_real_distribution<double>(0.0, 1.0)(g));
    if (glm::dot(axis, d) < cosHalf) continue;  // d outside the cone
    Rgb bound = ext->unshotIntensityBound(scene.wall, axis, cosHalf), I = ext->unshotIntensity(scene.wall, d);
    for (int c = 0; c < 3; ++c) EXPECT_GE(bound[c], I[c]);
  }
}

TEST(IsShooting, PullSumsUnshotLightAndKeepsUnchangedNodes) {
  testhost::Scene scene;
  auto ext = testhost::configured();
  ext->attach(scene.host);
  unsigned seed = 10;
  for (NodeId leaf : scene.floorLeaves) ext->reflectShot(leaf, someSamples(Vec3(0, 0, 1), seed++));
  ext->reflectShot(scene.wall, someSamples(Vec3(1, 0, 0), seed++));
  scene.host.pullAll(*ext);
  Rgb kids(0.0);
  for (NodeId leaf : scene.floorLeaves) kids += ext->unshotPower(leaf);
  EXPECT_LT(relDiff(ext->unshotPower(scene.floor), kids), 1e-6);
  EXPECT_LT(relDiff(ext->unshotPower(scene.cluster), kids + ext->unshotPower(scene.wall)), 1e-6);
  auto visits = [&] {
    for (const auto& s : ext->stats())
      if (s.name == "pull_node_visits") return s.value;
    return -1.0;
  };
  // Nothing changed: a second pull does no work and changes nothing.
  const double v = visits();
  const Rgb total = ext->light(scene.cluster)->power;
  scene.host.pullAll(*ext);
  EXPECT_EQ(visits(), v);
  EXPECT_EQ(ext->light(scene.cluster)->power, total);
  // The floor shoots: its subtree's unshot light goes, the wall's stays; the leaves' total is
  // untouched, and above the leaves no total is kept while shooting (hr/extension.h, pull: nothing
  // reads it then).
  Rgb leavesTotal(0.0);
  for (NodeId leaf : scene.floorLeaves) leavesTotal += ext->light(leaf)->power;
  ext->shot(scene.floor);
  for (NodeId leaf : scene.floorLeaves) EXPECT_EQ(ext->unshotPower(leaf), Rgb(0.0));
  scene.host.pullAll(*ext);
  EXPECT_EQ(ext->unshotLight(scene.floor), nullptr);
  EXPECT_LT(relDiff(ext->unshotPower(scene.cluster), ext->unshotPower(scene.wall)), 1e-6);
  Rgb after(0.0);
  for (NodeId leaf : scene.floorLeaves) after += ext->light(leaf)->power;
  EXPECT_EQ(after, leavesTotal);
  EXPECT_EQ(ext->light(scene.floor), nullptr);
  EXPECT_EQ(ext->light(scene.cluster), nullptr);
}

TEST(IsShooting, ASplitHandsTheUnshotLightDown) {
  testhost::Scene scene;
  auto ext = testhost::configured();
  ext->attach(scene.host);
  ext->reflectShot(scene.wall, someSamples(Vec3(1, 0, 0), 20));
  const Rgb unshot = ext->unshotPower(scene.wall);
  auto kids = scene.host.split(scene.wall);
  ext->split(scene.wall, kids);
  Rgb sum(0.0);
  for (NodeId k : kids) sum += ext->unshotPower(k);
  EXPECT_LT(relDiff(sum, unshot), 1e-6);
}

}  // namespace
