// The pull: a parent's distribution is the sum of its children's. Checked: the power of a pulled node
// equals its children's (exactly, up to float rounding), pointwise it stays within a stated distance
// of the exact sum, with eps -> 0 it is the exact sum, a sum of 64 exponent-100 lobes stays a small
// tree (the plain union of the same trees is printed beside it), clusters over differently oriented
// elements keep their children's power, and a split hands a leaf's light to its children.
#include <glossy/haar_sum.h>
#include <glossy/is_options.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "compare.h"
#include "fake_host.h"

namespace {

using glossy::Rgb;
using glossy::Vec3;
using glossy::kPi;
using testhost::NodeId;

using testdirs::relDiff;

/// Lights every glossy leaf of the scene with a few samples from random directions above it.
void lightLeaves(const testhost::FakeHost& host, glossy::IlluminationSamples& ext, unsigned seed, int perLeaf = 3) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (NodeId leaf : host.simulatedLeaves(ext)) {
    Vec3 n = host.info(leaf).normal;
    std::vector<hr::IncidentSample> s;
    for (int k = 0; k < perLeaf; ++k)
      s.push_back(testhost::sample(testhost::around(n, std::acos(u(g)), 2.0 * kPi * u(g)), Rgb(1.0 + u(g), u(g), 0.5)));
    ext.reflect(leaf, s);
  }
}

Rgb childSum(const glossy::IlluminationSamples& ext, std::span<const NodeId> kids, const Vec3& d) {
  Rgb s(0.0);
  for (NodeId k : kids) s += ext.intensity(k, d);
  return s;
}

TEST(IsPull, ParentIsTheSumOfItsChildren) {
  // Power: exact up to float rounding (1e-6). Pointwise: the re-projection keeps a cell whole where
  // its sub-cells' means differ by less than eps of its mean, so the parent is the sum smoothed at
  // that tolerance: relative L1 distance to the exact sum within eps / 4 at the default eps 0.5.
  for (const char* basis : {"haar", "tetra", "sh"}) {
    testhost::Scene scene;
    auto ext = testhost::configured({{"basis", basis}});
    ext->attach(scene.host);
    lightLeaves(scene.host, *ext, 1);
    scene.host.pullAll(*ext);
    auto kids = scene.host.children(scene.floor);
    Rgb sum(0.0);
    for (NodeId k : kids) sum += ext->light(k)->power;
    EXPECT_LT(relDiff(ext->light(scene.floor)->power, sum), 1e-6) << basis;
    // The distributions themselves: intensity() clamps spherical harmonics' negative ringing, and a
    // sum of clamped children is not the clamped sum.
    auto parent = [&](const Vec3& d) { return hr::luminance(glossy::eval(ext->light(scene.floor)->dist, d)); };
    auto sumOfKids = [&](const Vec3& d) {
      double v = 0.0;
      for (NodeId k : kids) v += hr::luminance(glossy::eval(ext->light(k)->dist, d));
      return v;
    };
    double l1 = testdirs::relativeL1(parent, sumOfKids, Vec3(0, 0, 1));
    std::printf("%-5s floor = sum of its four leaves: relative L1 %.4f, %zu coefficients\n", basis, l1,
                glossy::coefficients(ext->light(scene.floor)->dist));
    EXPECT_LT(l1, std::string(basis) == "haar" ? 0.125 : 1e-6) << basis;
  }
}

TEST(IsPull, WithVanishingEpsTheSumIsExact) {
  testhost::Scene scene;
  auto ext = testhost::configured({{"dir-eps", "1e-9"}, {"dir-max-level", "5"}});
  ext->attach(scene.host);
  lightLeaves(scene.host, *ext, 2);
  scene.host.pullAll(*ext);
  auto kids = scene.host.children(scene.floor);
  std::mt19937_64 g(4);
  double worst = 0.0;
  const double peak = hr::maxComponent(ext->light(scene.floor)->peak);
  for (int k = 0; k < 20000; ++k) {
    Vec3 d = testdirs::sphere(g);
    Rgb want = childSum(*ext, kids, d), got = ext->intensity(scene.floor, d);
    worst = std::max(worst, hr::maxComponent(glm::abs(got - want)) / peak);
  }
  std::printf("eps 1e-9: largest difference from the exact sum %.2e of the peak\n", worst);
  EXPECT_LT(worst, 1e-6) << "float rounding only";
}

/// 64 exponent-100 lobes: the leaves of a 2 x 2 m glossy floor cut 8 x 8, lit by a point light 1 m
/// above its centre (the mirror directions fan out over the hemisphere).
struct SixtyFour {
  testhost::FakeHost host;
  NodeId floor;
  std::vector<NodeId> leaves;
  std::vector<Vec3> toLight;
  SixtyFour() {
    std::uint32_t g = host.addMaterial(testhost::glossyMaterial(100.0));
    floor = host.addElement(Vec3(0.0), Vec3(0, 0, 1), 4.0, g);
    // Three quadtree levels: leaf (i, j) of the 8 x 8 grid by the path of its quadrants.
    std::vector<std::pair<NodeId, glm::dvec2>> level = {{floor, glm::dvec2(0.0)}};
    double half = 1.0;
    for (int l = 0; l < 3; ++l) {
      std::vector<std::pair<NodeId, glm::dvec2>> next;
      half *= 0.5;
      for (auto [id, c] : level) {
        auto kids = host.split(id);
        const glm::dvec2 off[4] = {{-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
        for (int k = 0; k < 4; ++k) next.push_back({kids[std::size_t(k)], c + half * off[k]});
      }
      level = next;
    }
    host.addCluster({floor});
    for (auto [id, c] : level) {
      leaves.push_back(id);
      toLight.push_back(glm::normalize(Vec3(-c.x, -c.y, 1.0)));
      host.node(id).info.center = Vec3(c, 0.0);
    }
  }
};

TEST(IsPull, SixtyFourLobesStayASmallTree) {
  // Levels 2 to 8 (as in the measured 230,792-node union), eps 0.5; the floor's leaves lit by a point
  // light above its centre, then by 64 random directions (lobes that overlap least). Bound: the pulled
  // floor holds no more nodes than 8 of its leaves' trees, with the leaves' power to 1e-6 and within
  // eps / 4 of the exact sum in relative L1.
  for (bool random : {false, true}) {
    SixtyFour s;
    auto ext = testhost::configured({{"dir-max-level", "8"}, {"dir-min-level", "2"}});
    ext->attach(s.host);
    std::mt19937_64 g(21);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (std::size_t i = 0; i < s.leaves.size(); ++i) {
      Vec3 wi = random ? testhost::around(Vec3(0, 0, 1), std::acos(u(g)), 2.0 * kPi * u(g)) : s.toLight[i];
      hr::IncidentSample smp = testhost::sample(wi, Rgb(3.0, 2.0, 1.0));
      ext->reflect(s.leaves[i], {&smp, 1});
    }
    s.host.pullAll(*ext);
    glossy::HaarDistribution unionTree;
    Rgb leafPower(0.0);
    std::size_t leafNodes = 0;
    std::vector<glossy::HaarTerm> terms;
    for (NodeId l : s.leaves) {
      const auto& h = std::get<glossy::HaarDistribution>(ext->light(l)->dist);
      unionTree.add(h);
      leafPower += ext->light(l)->power;
      leafNodes += h.coefficients();
      terms.push_back({&h, ext->light(l)->frame});
    }
    const auto& floor = std::get<glossy::HaarDistribution>(ext->light(s.floor)->dist);
    // The same 64 trees summed at once (as a cluster of 64 elements would) rather than four at a time.
    auto once = glossy::haarSum(terms, ext->light(s.floor)->frame, ext->basis().haar);
    double l1 = testdirs::relativeL1([&](const Vec3& d) { return hr::luminance(ext->intensity(s.floor, d)); },
                                     [&](const Vec3& d) { return hr::luminance(childSum(*ext, s.leaves, d)); }, Vec3(0, 0, 1));
    std::printf("64 lobes (n = 100, levels 2-8, %s): leaves %zu nodes in all (mean %zu); plain union %zu nodes "
                "(%zu bytes); pulled through the quadtree %zu nodes (%zu bytes), summed at once %zu nodes; "
                "relative L1 to the exact sum %.4f\n",
                random ? "random directions" : "point light", leafNodes, leafNodes / 64, unionTree.coefficients(),
                unionTree.bytes(), floor.coefficients(), floor.bytes(), once.coefficients(), l1);
    EXPECT_LE(floor.coefficients(), 8 * leafNodes / 64);
    EXPECT_LE(once.coefficients(), 8 * leafNodes / 64);
    EXPECT_LT(relDiff(ext->light(s.floor)->power, leafPower), 1e-6);
    EXPECT_LT(relDiff(once.leafIntegral(), leafPower), 1e-6);
    EXPECT_LT(l1, 0.125);
  }
}

TEST(IsPull, ClusterOverDifferentlyOrientedElementsKeepsTheirPower) {
  // The cluster holds the floor (+z), the wall (+x) and the tilted leaf, each in its own frame, in
  // the world frame: their cells are clipped against its cells, so the power is exact (1e-6) and the
  // shape within the refiner's tolerance (relative L1 within eps / 4).
  testhost::Scene scene;
  auto ext = testhost::configured();
  ext->attach(scene.host);
  lightLeaves(scene.host, *ext, 3);
  scene.host.pullAll(*ext);
  const auto* c = ext->light(scene.cluster);
  ASSERT_NE(c, nullptr);
  EXPECT_TRUE(c->frame.same(glossy::Frame::world()));
  auto kids = scene.host.children(scene.cluster);
  Rgb sum(0.0);
  for (NodeId k : kids)
    if (ext->light(k)) sum += ext->light(k)->power;
  double l1 = testdirs::relativeL1([&](const Vec3& d) { return hr::luminance(ext->intensity(scene.cluster, d)); },
                                   [&](const Vec3& d) { return hr::luminance(childSum(*ext, kids, d)); }, Vec3(0, 0, 1));
  std::printf("cluster over +z, +x and tilted elements: power off by %.2e, relative L1 %.4f, %zu coefficients\n",
              relDiff(c->power, sum), l1, glossy::coefficients(c->dist));
  EXPECT_LT(relDiff(c->power, sum), 1e-6);
  EXPECT_LT(l1, 0.125);
  // A cluster whose children share one frame keeps that frame.
  auto ext2 = testhost::configured();
  SixtyFour s;
  ext2->attach(s.host);
  hr::IncidentSample smp = testhost::sample(Vec3(0.2, 0.1, 1.0), Rgb(1.0));
  for (NodeId l : s.leaves) ext2->reflect(l, {&smp, 1});
  s.host.pullAll(*ext2);
  EXPECT_TRUE(ext2->light(s.host.root())->frame.same(ext2->light(s.floor)->frame));
}

TEST(IsPull, SplitHandsTheLightDownByArea) {
  for (const char* basis : {"haar", "tetra", "sh"}) {
    testhost::Scene scene;
    auto ext = testhost::configured({{"basis", basis}});
    ext->attach(scene.host);
    NodeId leaf = scene.wall;
    std::vector<hr::IncidentSample> s = {testhost::sample(Vec3(1, 0.3, 0.2), Rgb(2.0)), testhost::sample(Vec3(1, -0.5, 0.1), Rgb(0.5))};
    ext->reflect(leaf, s);
    const Rgb before = ext->light(leaf)->power;
    auto kids = scene.host.split(leaf);
    ext->split(leaf, kids);
    Rgb sum(0.0);
    std::mt19937_64 g(8);
    for (NodeId k : kids) {
      ASSERT_NE(ext->light(k), nullptr) << basis << ": a freshly split sender is never dark";
      sum += ext->light(k)->power;
      for (int i = 0; i < 200; ++i) {
        Vec3 d = testdirs::sphere(g);
        EXPECT_LT(relDiff(ext->intensity(k, d), 0.25 * ext->intensity(leaf, d)), 1e-6);
      }
    }
    EXPECT_LT(relDiff(sum, before), 1e-6) << basis << ": split preserves power";
    EXPECT_EQ(ext->powerChange(), 0.0) << basis << ": a split changes no power";
    ext->attach(scene.host);
    ext->pull(leaf, kids);
    EXPECT_LT(relDiff(ext->light(leaf)->power, before), 1e-6) << basis;
  }
}

}  // namespace
