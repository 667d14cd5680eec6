// The VISION-like host hands the display its surfaces' exact normals at every cell corner
// (hr::Solution::cornerNormals, the "normals" section): a sphere's are (p - c) / r to rounding, a
// plane's its own normal. The display shades a curved leaf at the normal interpolated from them; the
// estimate it falls back on (the area-weighted mean of the flat cells meeting at a vertex) leans
// toward the larger cells of an adaptively refined sphere. A damaged section is refused.
#include <gtest/gtest.h>
#include <hr/extension.h>
#include <hr/extension_display.h>
#include <hr/solution.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "vision_helpers.h"

namespace {

/// Shows the normal it is asked at: radiance = normal + (1, 1, 1), on the shiny material only.
class NormalProbe : public hr::Extension {
 public:
  std::string_view name() const override { return "normal-probe"; }
  bool simulates(const hr::MaterialInfo& m) const override { return m.specular.x > 0.0; }
  hr::Rgb radiance(hr::NodeId, const hr::Vec3&) const override { return hr::Rgb(-1.0); }
  hr::Rgb radiance(hr::NodeId, const hr::Vec3&, const hr::Vec3& n) const override { return n + hr::Vec3(1.0); }
};

double degreesBetween(const hr::Vec3& a, const hr::Vec3& b) {
  return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) * 180.0 / hr::kPi;
}

/// A sphere of radius 0.5 at the origin (object 0, shiny) over a floor, lit by a small lamp close to
/// one side: its leaves are refined unevenly, small toward the lamp and large away from it.
const hr::Solution& litSphere() {
  static const hr::Solution solved = [] {
    const std::string scene = R"({ "name": "normals",
    "materials": { "shiny": { "diffuse": [0.5, 0.5, 0.5], "specular": [0.3, 0.3, 0.3], "exponent": 200 },
                   "grey": { "diffuse": [0.5, 0.5, 0.5] }, "lamp": { "emission": [50, 50, 50] } },
    "objects": [ { "type": "sphere", "material": "shiny", "center": [0, 0, 0], "radius": 0.5 },
                 { "type": "quad", "material": "grey", "vertices": [[-3,-3,-0.5],[3,-3,-0.5],[3,3,-0.5],[-3,3,-0.5]] },
                 { "type": "quad", "material": "lamp", "vertices": [[0.55,-0.1,0.9],[0.55,0.1,0.9],[0.75,0.1,0.7],[0.75,-0.1,0.7]] } ] })";
  hr::SolverOptions opt;
  opt.eps = 2e-4;
  opt.maxLevel = 6;
  visiontest::Solved s = visiontest::solveText(scene, opt);
  return vision::makeSolution(s.scene, *s.h, vision::Display::Smooth);
  }();
  return solved;
}

TEST(VisionNormals, TheDisplayShadesACurvedLeafAtItsSurfacesOwnNormals) {
  const hr::Vec3 c(0.0);
  const hr::Solution sol = litSphere();
  ASSERT_EQ(sol.cornerNormals.size(), sol.elements.size());
  // The host's normals: exact on the sphere, the plane's own on the floor.
  double worstHost = 0.0;
  std::size_t sphereLeaves = 0;
  double smallest = 1e300, largest = 0.0;
  for (std::size_t i = 0; i < sol.elements.size(); ++i) {
    const hr::SolutionElement& e = sol.elements[i];
    const hr::Patch& p = sol.patches[e.patch];
    for (int k = 0; k < e.poly.n; ++k) {
      const hr::Vec3 exact = p.object == 0 ? glm::normalize(e.poly.v[k] - c) : p.normal;
      worstHost = std::max(worstHost, degreesBetween(sol.cornerNormals[i][std::size_t(k)], exact));
    }
    if (p.object == 0) ++sphereLeaves, smallest = std::min(smallest, e.poly.area()), largest = std::max(largest, e.poly.area());
  }
  EXPECT_LT(worstHost, 1e-6) << "degrees";
  ASSERT_GT(largest, 8.0 * smallest) << "the sphere must be refined unevenly for this test to say anything";
  // The display at every sphere cell's corners, both ways: still images (the normal interpolated at
  // a point) and the viewer's per-vertex values.
  NormalProbe probe;
  auto worstShading = [&](const hr::Solution& s) {
    hr::ExtensionDisplay d(s, probe);
    const hr::Vec3 eye(0.3, -3.0, 2.0);
    d.update(eye);
    double worst = 0.0;
    for (std::uint32_t i = 0; i < s.elements.size(); ++i) {
      const hr::SolutionElement& e = s.elements[i];
      if (s.patches[e.patch].object != 0 || !d.simulated(i)) continue;
      for (int k = 0; k < e.poly.n; ++k) {
        const hr::Vec3 v = e.poly.v[std::size_t(k)], exact = glm::normalize(v - c);
        const hr::Vec3 still = d.radiance(i, v, glm::normalize(eye - v)) - hr::Vec3(1.0);
        const hr::Vec3 vertex = d.cornerValues()[d.firstCorner(i) + std::uint32_t(k)] - hr::Vec3(1.0);
        worst = std::max({worst, degreesBetween(still, exact), degreesBetween(vertex, exact)});
      }
    }
    return worst;
  };
  const double exact = worstShading(sol);
  hr::Solution estimated = sol;
  estimated.cornerNormals.clear();
  const double estimate = worstShading(estimated);
  std::printf("%zu sphere cells (areas %.3g to %.3g m^2): shading normals off by %.2e degrees from the host's, %.3f from the estimate\n",
              sphereLeaves, smallest, largest, exact, estimate);
  EXPECT_LT(exact, 1e-4) << "degrees";
  EXPECT_GT(estimate, 0.05) << "the estimate this replaces leans toward larger cells (else the test shows nothing)";
}

TEST(VisionNormals, ADamagedNormalsSectionIsRefused) {
  const hr::Solution& sol = litSphere();
  const std::string good = *hr::findSection(sol, hr::kCornerNormals);
  auto refused = [&](const std::string& bytes) {
    hr::Solution s = sol;
    hr::setSection(s, hr::kCornerNormals, bytes);
    try {
      hr::reconstruct(s);
    } catch (const hr::InputError& e) {
      return std::string(e.what()).find("\"normals\"") != std::string::npos;
    }
    return false;
  };
  EXPECT_FALSE(refused(good));
  EXPECT_TRUE(refused(good.substr(0, good.size() - 8))) << "truncated";
  EXPECT_TRUE(refused(good + std::string(8, '\0'))) << "too long";
  std::string nan = good;
  const double q = std::nan("");
  std::memcpy(nan.data() + std::strlen(hr::kCornerNormals), &q, sizeof q);
  EXPECT_TRUE(refused(nan)) << "not finite";
  std::string longer = good;
  const double two = 2.0;
  std::memcpy(longer.data() + std::strlen(hr::kCornerNormals), &two, sizeof two);
  EXPECT_TRUE(refused(longer)) << "not of unit length";
  std::string foreign = good;
  foreign[0] = 'X';
  EXPECT_TRUE(refused(foreign)) << "without its magic";
}

}  // namespace
