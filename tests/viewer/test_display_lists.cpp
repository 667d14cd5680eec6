// The viewer's two lists reproduce the still images' shading: at random points of every triangle,
// linear interpolation of the per-vertex values (what the rasteriser does) equals hr::interpolate's
// B / pi and ExtensionDisplay::radiance there (what hr::render shades), to float precision; the
// lists split the leaves by what the extension simulates, and every triangle faces its patch's front.
#include "display_lists.h"
#include "view_fixture.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>

namespace {

using viewtest::threeLights;

TEST(DisplayLists, InterpolateLikeTheStillRenderer) {
  const auto& l = threeLights();
  hr::ExtensionDisplay d(l.sol, *l.ext);
  d.update(hr::Vec3(0.3, 1.4, -2.0));
  view::DisplayLists lists = view::buildDisplayLists(l.sol, &d);
  ASSERT_GT(lists.glossy.triangleLeaf.size(), 0u);
  ASSERT_GT(lists.diffuse.triangleLeaf.size(), 0u);
  std::vector<float> glossy(lists.glossy.points.size());
  view::glossyRadiance(lists.glossy, d, glossy.data());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  double worst = 0.0;
  std::size_t checked = 0;
  for (const view::DisplayList* list : {&lists.diffuse, &lists.glossy}) {
    const bool isGlossy = list == &lists.glossy;
    for (std::size_t t = 0; t < list->triangleLeaf.size(); ++t) {
      const std::uint32_t leaf = list->triangleLeaf[t];
      EXPECT_EQ(d.simulated(leaf), isGlossy);
      const std::uint32_t* tri = &list->triangles[3 * t];
      auto pos = [&](int k) { const float* p = &list->points[3 * tri[k]]; return hr::Vec3(p[0], p[1], p[2]); };
      auto val = [&](const std::vector<float>& a, int k) { const float* p = &a[3 * tri[k]]; return hr::Rgb(p[0], p[1], p[2]); };
      const hr::Vec3& n = l.sol.patches[l.sol.elements[leaf].patch].normal;
      EXPECT_GT(glm::dot(glm::cross(pos(1) - pos(0), pos(2) - pos(0)), n), 0.0) << "front faces wind counter-clockwise";
      for (int s = 0; s < 4; ++s) {
        double a = u01(rng), b = u01(rng);
        if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
        const double w[3] = {1.0 - a - b, a, b};
        hr::Vec3 x = w[0] * pos(0) + w[1] * pos(1) + w[2] * pos(2);
        hr::Rgb shown(0.0), truth = hr::interpolate(l.sol, leaf, x) / hr::kPi;
        for (int k = 0; k < 3; ++k) shown += w[k] * val(list->diffuse, k);
        if (isGlossy) {
          for (int k = 0; k < 3; ++k) shown += w[k] * val(glossy, k);
          truth += d.radiance(leaf, x);
        }
        double err = hr::maxComponent(glm::abs(shown - truth)) / std::max(1e-3, hr::maxComponent(truth));
        worst = std::max(worst, err);
        ++checked;
      }
    }
  }
  RecordProperty("worst_relative_error_x1e9", int(worst * 1e9));
  EXPECT_LT(worst, 1e-5) << "over " << checked << " points";
}


// No T-junctions: no triangle edge of either list has a leaf corner at its midpoint or quarter
// points. Where a leaf met finer neighbours the rasteriser left pinholes along its edge, through
// which the black background darkened a pixel by 6/255 (ViewFrames.TwoEyesMoveTheHighlightNotThe-
// DiffuseLight on three lights at eps 6e-5); each leaf now takes its neighbours' corners on its
// edges as vertices of its own (display_lists.cpp). Without that: 341 of 70,713 edges here.
TEST(DisplayLists, LeavesMeetWithoutTJunctions) {
  const auto& l = threeLights();
  hr::ExtensionDisplay d(l.sol, *l.ext);
  view::DisplayLists lists = view::buildDisplayLists(l.sol, &d);
  auto key = [](const hr::Vec3& p) {
    return std::array<long long, 3>{std::llround(p.x * 1e6), std::llround(p.y * 1e6), std::llround(p.z * 1e6)};
  };
  std::set<std::array<long long, 3>> corners;
  for (const auto& e : l.sol.elements)
    if (e.leaf())
      for (int k = 0; k < e.poly.n; ++k) corners.insert(key(e.poly.v[k]));
  std::size_t bad = 0, edges = 0;
  for (const view::DisplayList* list : {&lists.diffuse, &lists.glossy})
    for (std::size_t t = 0; t < list->triangleLeaf.size(); ++t) {
      const std::uint32_t* tri = &list->triangles[3 * t];
      auto pos = [&](int k) { const float* p = &list->points[3 * tri[k]]; return hr::Vec3(p[0], p[1], p[2]); };
      for (int k = 0; k < 3; ++k, ++edges)
        for (double f : {0.25, 0.5, 0.75})
          bad += corners.count(key((1.0 - f) * pos(k) + f * pos((k + 1) % 3))) ? 1 : 0;
    }
  std::printf("%zu triangle edges, %zu leaf corners inside one\n", edges, bad);
  EXPECT_EQ(bad, 0u);
}

}  // namespace
