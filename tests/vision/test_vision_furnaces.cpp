// A curved furnace on the VISION-like host, solved without tessellation: a closed sphere facing
// inward. Every surface reflects rho = 0.5 and emits L_e = 1, so
// at equilibrium every point has B = pi L_e / (1 - rho) = 2 pi W/m^2 (B = B_e + rho B, irradiance B
// from a closed surround of radiosity B), and what is emitted is absorbed. Tolerances: 1 % per
// element, 0.5 % for the balance (the issue's acceptance bars). Measured: worst element 9e-4,
// absorbed / emitted 0.99909 (before a point inside the sender's own rectangle was handled apart,
// its contour enclosed it: 0.99344). The same sphere's smooth display (corners and pixels) within 1 %
// of the closed form. A sphere inside a closed box: both bars at the default threshold.
#include <gtest/gtest.h>
#include <hr/output.h>
#include <hr/solution.h>

#include <algorithm>
#include <cmath>

#include "../helpers.h"
#include "vision_helpers.h"

namespace {

constexpr double kRho = 0.5;

hr::SolverOptions furnaceOptions() {
  hr::SolverOptions o = testutil::options(1e-3, 4);
  o.maxIterations = 200;
  o.tolerance = 1e-5;
  return o;
}

void checkFurnace(const visiontest::Solved& s) {
  ASSERT_TRUE(s.stats.converged);
  EXPECT_EQ(s.stats.links, 0u) << "link-less shooting stores no links";
  const double expected = hr::kPi / (1.0 - kRho);
  double worst = 0.0;
  std::size_t n = 0;
  const vision::Element* at = nullptr;
  for (const vision::Element* e : s.leaves()) {
    for (int c = 0; c < 3; ++c)
      if (std::abs(e->B[c] / expected - 1.0) > worst) worst = std::abs(e->B[c] / expected - 1.0), at = e;
    ++n;
  }
  EXPECT_GT(n, s.h->surfaces().size()) << "the solve refined the whole primitives";
  EXPECT_LT(worst, 0.01) << "every element's B within 1 % of pi Le / (1 - rho); " << n << " leaves; worst on surface " << at->surface
                        << " at u " << at->rect.u0 << ".." << at->rect.u1 << ", v " << at->rect.v0 << ".." << at->rect.v1
                        << ", B/expected " << at->B.y / expected;
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(s.stats.absorbedW[c] / s.stats.emittedW[c], 1.0, 0.005) << "emitted = absorbed within 0.5 %";
    EXPECT_LT(s.stats.escapedW[c], 1e-3 * s.stats.emittedW[c]) << "nothing escapes a closed furnace";
  }
  std::printf("furnace: %zu surfaces, %zu leaves, worst element %.3g, absorbed/emitted %.5f\n", s.h->surfaces().size(), n,
              worst, s.stats.absorbedW.y / s.stats.emittedW.y);
}

const std::string kMaterials = R"({ "materials": { "g": { "diffuse": [0.5,0.5,0.5], "emission": [1,1,1] } }, )";

TEST(VisionFurnace, InwardSphere) {
  hr::Scene sc = hr::parseScene(kMaterials + R"("objects": [ { "type": "sphere", "material": "g", "center": [0,0,0], "radius": 1 } ] })", "");
  sc.objects[0].inward = true;  // JSON spheres face out; MGF's negative radius is the inward one
  auto s = visiontest::solve(std::move(sc), furnaceOptions());
  EXPECT_EQ(s.h->surfaces().size(), 1u) << "the sphere is one whole surface, not a tessellation";
  checkFurnace(s);
  // The smooth display of the same solve (vision_host/src/smooth.cpp): every display corner and every
  // pixel seen from inside shows the closed form too; the sphere's seam and poles are where a wrong
  // join would show.
  hr::Solution sol = vision::makeSolution(s.scene, *s.h, vision::Display::Smooth);
  const double B = hr::kPi / (1.0 - kRho);
  double worst = 0.0;
  for (std::size_t i = 0; i < sol.elements.size(); ++i)
    for (int k = 0; k < sol.elements[i].poly.n; ++k) worst = std::max(worst, std::abs(sol.cornerRadiosity[i][k].y / B - 1.0));
  EXPECT_LT(worst, 0.01) << "every smoothed corner within 1 % of pi Le / (1 - rho)";
  hr::Camera cam;
  cam.eye = hr::Vec3(0.0, 0.0, 0.3), cam.lookAt = hr::Vec3(0.0, 0.0, -1.0), cam.up = hr::Vec3(0.0, 1.0, 0.0);
  cam.fovYDeg = 120.0, cam.width = cam.height = 64;
  hr::Image img = hr::render(sol, cam);
  double worstPx = 0.0;
  for (std::size_t p = 0; p < img.objectId.size(); ++p) worstPx = std::max(worstPx, std::abs(img.rgb[3 * p + 1] / 2.0 - 1.0));
  EXPECT_LT(worstPx, 0.01) << "every pixel within 1 % of L_e / (1 - rho) = 2 W/(m^2 sr)";
  std::printf("furnace sphere smooth: %zu cells, worst corner %.3g, worst pixel %.3g\n", sol.elements.size(), worst, worstPx);
}

// Where three faces of the box meet, every sender but the adjacent faces lights the part near the
// edges less: an element's light pushed evenly to its children put the rows along the edges 2 % high
// and the next rows 2 % low (worst 0.0212 at this eps; 0.041 at eps 1e-3) before the light kept at a
// receiver was placed by quarters and its unevenness held to the budget (shoot.cpp, settle).
// Measured: worst element 0.0075 (an element in the sphere's penumbra, shadow-ray noise), absorbed /
// emitted 0.99921, 1920 leaves, 28-29 s of CPU on 2 threads (37-65 s wall on a shared, loaded
// machine). At maxLevel 3 (480 leaves) the code before passed too (0.0071): the edge rows are
// wider there, so this test keeps maxLevel 4.
TEST(VisionFurnace, ASphereInsideAClosedBoxAtTheDefaultThreshold) {
  hr::SolverOptions o = furnaceOptions();
  o.eps = hr::SolverOptions{}.eps;
  hr::Scene sc = hr::parseScene(kMaterials + R"("objects": [
    { "type": "box", "material": "g", "min": [-1,-1,-1], "max": [1,1,1], "facing": "inward" },
    { "type": "sphere", "material": "g", "center": [0,0,0], "radius": 0.5 } ] })", "");
  auto s = visiontest::solve(std::move(sc), o);
  EXPECT_EQ(s.h->surfaces().size(), 7u) << "six box faces and the whole sphere, none tessellated";
  checkFurnace(s);
}

}  // namespace
