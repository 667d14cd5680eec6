// The VISION-like host hands the display its curved objects (hr::Solution::surfaces, the "surfaces"
// section): a sphere's normal at a cell corner is (p - c) / r to rounding, a plane has none. The
// display shades a curved leaf at them; the estimate it falls back on (the area-weighted mean of the
// flat cells meeting at a vertex) leans toward the larger cells of an adaptively refined sphere.
// (The section's codec is tested with the BRIGHT-like host, tests/test_curved_surface.cpp.)
#include <gtest/gtest.h>
#include <hr/solution.h>

#include "../normal_probe.h"
#include "vision_helpers.h"

namespace {

TEST(VisionNormals, TheDisplayShadesACurvedLeafAtItsSurfacesOwnNormals) {
  hr::SolverOptions opt;
  opt.eps = 2e-4;
  opt.maxLevel = 6;
  visiontest::Solved solved = visiontest::solveText(testutil::shinySphereScene("{}"), opt);
  const hr::Solution sol = vision::makeSolution(solved.scene, *solved.h, vision::Display::Smooth);
  ASSERT_EQ(sol.surfaces.size(), 3u);
  // The solution's normals: exact on the sphere (radius 0.5 at the origin), none on the floor and the lamp.
  double worstHost = 0.0, smallest = 1e300, largest = 0.0;
  std::size_t sphereLeaves = 0;
  for (const hr::SolutionElement& e : sol.elements) {
    const hr::Patch& p = sol.patches[e.patch];
    for (int k = 0; k < e.poly.n; ++k) {
      const hr::Vec3 n = hr::surfaceNormal(sol, e.patch, e.poly.v[k]);
      if (p.object == 0)
        worstHost = std::max(worstHost, testutil::degreesBetween(n, e.poly.v[k]));
      else
        EXPECT_EQ(n, hr::Vec3(0.0));
    }
    if (p.object == 0) ++sphereLeaves, smallest = std::min(smallest, e.poly.area()), largest = std::max(largest, e.poly.area());
  }
  EXPECT_LT(worstHost, 1e-6) << "degrees";
  ASSERT_GT(largest, 8.0 * smallest) << "the sphere must be refined unevenly for this test to say anything";
  // The display at every sphere cell's corners, both ways: still images and the viewer's vertices.
  std::size_t corners = 0;
  const double exact = testutil::worstShadingDegrees(sol, corners);
  hr::Solution estimated = sol;
  estimated.surfaces.clear();
  const double estimate = testutil::worstShadingDegrees(estimated, corners);
  std::printf("%zu sphere cells (areas %.3g to %.3g m^2): shading normals off by %.2e degrees from the sphere's, %.3f with the estimate\n",
              sphereLeaves, smallest, largest, exact, estimate);
  EXPECT_LT(exact, 1e-4) << "degrees";
  EXPECT_GT(estimate, 0.05) << "the estimate this replaces leans toward larger cells (else the test shows nothing)";
}

}  // namespace
