// The oracle's bound of a node's intensity over a cone must never be below what intensity() returns
// anywhere in the cone, for every basis and every kind of node (leaf, inner element, cluster in the
// world frame). Checked against a brute-force maximum over many directions in random cones, with no
// tolerance; how tight the bounds are is printed (bound / brute-force maximum).
#include <glossy/brdf.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "directions.h"
#include "fake_host.h"

namespace {

using glossy::Rgb;
using glossy::Vec3;
using glossy::kPi;
using testhost::NodeId;

struct Tightness {
  std::vector<double> ratios;
  void print(const char* what) {
    if (ratios.empty()) return;
    std::sort(ratios.begin(), ratios.end());
    std::printf("%-26s bound / true max over %zu lit cones: median %.3f, 90th percentile %.3f, worst %.3f\n", what,
                ratios.size(), ratios[ratios.size() / 2], ratios[ratios.size() * 9 / 10], ratios.back());
  }
};

TEST(IsBounds, NeverBelowTheLargestIntensityInTheCone) {
  for (const char* basis : {"haar", "tetra", "sh"}) {
    testhost::Scene scene(300.0);
    auto ext = testhost::configured({{"basis", basis}});
    ext->attach(scene.host);
    std::mt19937_64 g(17);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Vec3> peaks;  // mirror directions, where the maxima are
    for (NodeId leaf : scene.host.simulatedLeaves(*ext)) {
      Vec3 n = scene.host.info(leaf).normal;
      std::vector<hr::IncidentSample> s;
      for (int k = 0; k < 3; ++k) {
        Vec3 wi = testhost::around(n, std::acos(u(g)), 2.0 * kPi * u(g));
        s.push_back(testhost::sample(wi, Rgb(1.0 + u(g), u(g), 0.5)));
        peaks.push_back(glossy::mirror(wi, n));
      }
      ext->reflect(leaf, s);
    }
    scene.host.pullAll(*ext);
    const NodeId nodes[] = {scene.floorLeaves[0], scene.floor, scene.wall, scene.tilted, scene.cluster};
    Tightness leafT, clusterT;
    std::size_t checked = 0;
    for (NodeId node : nodes) {
      for (int c = 0; c < 300; ++c) {
        // Cones from 0.5 to 120 degrees, aimed half of the time near a highlight.
        double half = (0.5 + 119.5 * std::pow(u(g), 2.0)) * kPi / 180.0;
        Vec3 axis = c % 2 ? testdirs::sphere(g) : testhost::around(peaks[std::size_t(c) % peaks.size()], 0.3 * u(g), 2 * kPi * u(g));
        Rgb bound = ext->intensityBound(node, axis, std::cos(half));
        ASSERT_TRUE(hr::allFinite(bound));
        Rgb truth(0.0);
        auto visit = [&](const Vec3& d) {
          if (glm::dot(d, axis) < std::cos(half)) return;
          Rgb v = ext->intensity(node, d);
          truth = glm::max(truth, v);
          for (int ch = 0; ch < 3; ++ch)
            ASSERT_GE(bound[ch], v[ch]) << basis << " node " << node.value << " half-angle " << half << " channel " << ch;
        };
        visit(axis);
        for (const Vec3& p : peaks) visit(p);
        for (int k = 0; k < 3000; ++k) visit(testhost::around(axis, std::acos(1.0 - u(g) * (1.0 - std::cos(half))), 2 * kPi * u(g)));
        ++checked;
        if (truth.x > 1e-3 * ext->light(node)->peak.x) (node.isCluster() ? clusterT : leafT).ratios.push_back(bound.x / truth.x);
      }
    }
    EXPECT_EQ(checked, 1500u);
    std::printf("%s:\n", basis);
    leafT.print("  elements (own frames)");
    clusterT.print("  cluster (world frame)");
  }
}

TEST(IsBounds, WholeSphereAndDegenerateCones) {
  testhost::Scene scene;
  auto ext = testhost::configured();
  ext->attach(scene.host);
  hr::IncidentSample s = testhost::sample(Vec3(0.3, 0.1, 1.0), Rgb(1.0));
  ext->reflect(scene.floorLeaves[0], {&s, 1});
  NodeId leaf = scene.floorLeaves[0];
  const Rgb peak = ext->light(leaf)->peak;
  EXPECT_EQ(ext->intensityBound(leaf, Vec3(0, 0, 1), -1.0), peak);
  EXPECT_EQ(ext->intensityBound(leaf, Vec3(0.0), 0.5), peak) << "no axis: the whole sphere";
  EXPECT_EQ(ext->intensityBound(leaf, Vec3(0, 0, 1), std::nan("")), peak);
  Vec3 m = glossy::mirror(glm::normalize(Vec3(0.3, 0.1, 1.0)), Vec3(0, 0, 1));
  EXPECT_GE(ext->intensityBound(leaf, m, 1.0).x, ext->intensity(leaf, m).x) << "a zero-width cone";
  EXPECT_GE(ext->intensityBound(leaf, 5.0 * m, 2.0).x, ext->intensity(leaf, m).x) << "unnormalised axis, cos > 1";
  EXPECT_EQ(ext->intensityBound(scene.diffuse, Vec3(0, 0, 1), 0.0), Rgb(0.0)) << "a diffuse leaf sends nothing here";
}

}  // namespace
