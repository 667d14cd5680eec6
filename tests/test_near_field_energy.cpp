// Energy is never lost or created (issue 10, item 1): the scenes the issue measured, each balanced
// (emitted = absorbed + escaped, both measured by the independent audit) within 1 % at the default
// threshold, and within 3 % at any threshold from 1e-4 to 1.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include <hr/coplanar.h>

#include "helpers.h"

namespace {

/// A 2 x 2 m plate (rho 0.73) facing up at y = 0 and whatever else the scene adds.
std::string plateScene(const std::string& more) {
  return R"({ "materials": { "p": { "diffuse": [0.73,0.73,0.73] }, "e": { "emission": [1,1,1] } },
  "objects": [ { "type": "quad", "material": "p", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]] })" + more + "] }";
}

/// A 0.5 m emitter at height y facing down (or up).
std::string lamp(double y, bool down = true) {
  const std::string h = std::to_string(y);
  return down ? R"(, { "type": "quad", "material": "e", "vertices": [[-0.25,)" + h + ",-0.25],[0.25," + h + ",-0.25],[0.25," + h +
                    ",0.25],[-0.25," + h + ",0.25]] }"
              : R"(, { "type": "quad", "material": "e", "vertices": [[-0.25,)" + h + ",-0.25],[-0.25," + h + ",0.25],[0.25," + h +
                    ",0.25],[0.25," + h + ",-0.25]] }";
}

/// The built-in Cornell box with its lamp turned to face the ceiling, 1 mm under it.
std::string uplight() {
  std::string json = hr::kDefaultSceneJson;
  const std::string down = "[[0.75,1.999,0.75],[1.25,1.999,0.75],[1.25,1.999,1.25],[0.75,1.999,1.25]]";
  const std::string up = "[[0.75,1.999,0.75],[0.75,1.999,1.25],[1.25,1.999,1.25],[1.25,1.999,0.75]]";
  const auto at = json.find(down);
  if (at == std::string::npos) throw std::runtime_error("the built-in Cornell box's lamp moved");
  return json.replace(at, down.size(), up);
}

/// Largest |emitted - absorbed - escaped| / emitted over the channels that emit.
double imbalance(const std::string& json, double eps) {
  hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(json, "").settings);
  if (eps > 0) o.eps = eps;
  auto s = testutil::solveText(json, o);
  double worst = 0.0;
  for (int c = 0; c < 3; ++c)
    if (s.stats.emittedW[c] > 0)
      worst = std::max(worst, std::abs(s.stats.emittedW[c] - s.stats.absorbedW[c] - s.stats.escapedW[c]) / s.stats.emittedW[c]);
  std::printf("eps %g: imbalance %.2f %%, %zu links\n", o.eps, 100 * worst, s.stats.links);  // the note's table
  return worst;
}

// Before item 1: 36 % of a lamp 0.1 m above the plate unaccounted for.
TEST(NearField, SmallLampOverALargePlate) {
  for (double gap : {0.1, 0.01, 0.001}) EXPECT_LT(imbalance(plateScene(lamp(gap)), -1), 0.01) << "gap " << gap << " m";
}

// Before: 71 % lost 1 mm under the ceiling.
TEST(NearField, CornellUplight1mmUnderTheCeiling) { EXPECT_LT(imbalance(uplight(), -1), 0.01); }

// Before: 100 % reported escaped at 1e-6 m.
TEST(NearField, FacingLampsAMicronApart) {
  EXPECT_LT(imbalance(plateScene(lamp(1e-6, false) + lamp(1e-6 + 1e-6)), -1), 0.01);
}

// Before: energy created (-16 %) by a lamp z-fighting with the plate; a second plate above sends
// light back down onto both.
TEST(NearField, LampCoplanarWithTheReceiver) {
  const std::string ceiling = R"(, { "type": "quad", "material": "p", "vertices": [[-1,1,-1],[1,1,-1],[1,1,1],[-1,1,1]] })";
  EXPECT_LT(imbalance(plateScene(lamp(0.0, false) + ceiling), -1), 0.01);
}

// Before: -8 % at eps 0.05, -72 % at 1, -1298 % at 1000 (now refused: eps is at most 1).
TEST(NearField, AnyThresholdKeepsTheEnergy) {
  for (double eps : {1e-4, 1e-3, 1e-2, 0.1, 1.0}) {
    EXPECT_LT(imbalance(hr::kDefaultSceneJson, eps), 0.03) << "Cornell box, eps " << eps;
    EXPECT_LT(imbalance(uplight(), eps), 0.03) << "uplight, eps " << eps;
  }
}

}  // namespace

namespace {

/// The fraction of a leaf's area no coplanar patch covers, from a 16 x 16 grid (independent of the
/// solver's own count).
double openPart(const testutil::Solved& s, const hr::Element& e) {
  int open = 0;
  for (int a = 0; a < 16; ++a)
    for (int b = 0; b < 16; ++b) open += s.vis->coverOf(e.patch, e.poly.sample((a + 0.5) / 16, (b + 0.5) / 16)) == hr::kNone;
  return open / 256.0;
}

/// A furnace (rho 0.5, L_e 1, every seen point at B = 2 pi W/m^2) solved at eps with a cover in it:
/// checks, over the leaves `on` picks, the means weighted by each leaf's open part (open: 0-1), over
/// all of them and over those straddling the cover's outline, the worst straddling leaf with a
/// quarter or more open, and the balance. Tolerances: 2 % on the straddling mean and 10 % per
/// straddling leaf (the near-singular kernel at the contact, sampled by 32 rays: 18 % on one leaf at
/// eps 2e-4), 0.5 % on the open part's mean and the balance.
template <class On, class Open>
void expectFurnaceAroundCover(const char* json, double eps, const char* what, On on, Open open) {
  hr::SolverOptions o = testutil::options(eps, 5);
  o.maxIterations = 200;
  o.tolerance = 1e-5;
  auto s = testutil::solveText(json, o);
  ASSERT_TRUE(s.stats.converged);
  const double expected = 2.0 * hr::kPi;
  double straddle = 0.0, straddleArea = 0.0, all = 0.0, allArea = 0.0, worst = 0.0;
  int straddling = 0;
  for (std::uint32_t i = 0; i < s.h->elements().size(); ++i) {
    const hr::Element& e = s.h->element(i);
    if (!e.leaf() || !on(e)) continue;
    const double f = open(s, e), B = s.solver->radiosity()[i].y;
    all += f * e.area * B, allArea += f * e.area;
    if (f <= 0.0 || f >= 1.0) continue;
    straddle += f * e.area * B, straddleArea += f * e.area, ++straddling;
    if (f >= 0.25) worst = std::max(worst, std::abs(B / expected - 1.0));
  }
  ASSERT_GT(allArea, 0.0);
  ASSERT_GT(straddleArea, 0.0);
  std::printf("%d leaves straddle %s: mean %.4f, worst (a quarter open or more) %.4f; open part's mean %.4f (of 2 pi)\n",
              straddling, what, straddle / straddleArea / expected, worst, all / allArea / expected);
  EXPECT_GT(straddling, 8) << "the outline must cross leaves for this test to mean anything";
  EXPECT_NEAR(straddle / straddleArea / expected, 1.0, 0.02);
  EXPECT_LT(worst, 0.1);
  EXPECT_NEAR(all / allArea / expected, 1.0, 0.005);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR((s.stats.absorbedW[c] + s.stats.escapedW[c]) / s.stats.emittedW[c], 1.0, 0.005) << "channel " << c;
}

// A furnace with a box standing on its floor, turned so that the box's foot crosses the floor's
// quadtree leaves: every surface reflects rho = 0.5 and emits L_e = 1, so every point anyone can see
// has B = pi L_e / (1 - rho) = 2 pi W/m^2, the floor beside the box's foot included (the box's bottom
// covers the floor under it: coplanar.h). A floor leaf straddling the foot took its irradiance as
// the mean over all of its area, the covered part (where no light arrives) included. Before: the
// 22 straddling leaves' open-area mean 0.864 of 2 pi, worst leaf (a quarter open or more) -43 %,
// the floor's mean 0.991. Now radiosity and irradiance are those of the open part
// (SolverState::open): 1.0069, 2.6 %, 1.0009.
TEST(Covers, AFurnaceFloorBesideABoxsFootIsAsBrightAsTheRest) {
  const char* json = R"({ "materials": { "g": { "diffuse": [0.5,0.5,0.5], "emission": [1,1,1] } },
  "objects": [ { "type": "box", "material": "g", "min": [0,0,0], "max": [1,1,1], "facing": "inward" },
               { "type": "box", "material": "g", "min": [-0.15,0,-0.15], "max": [0.15,0.4,0.15],
                 "transform": { "translate": [0.45,0,0.55], "rotate_deg": [0,23,0] } } ] })";
  const std::uint32_t floorPatch = 5;  // the room box's faces come first; its floor is the sixth
  expectFurnaceAroundCover(json, 1e-3, "the foot", [&](const hr::Element& e) { return e.patch == floorPatch; }, openPart);
}


// A panel of the furnace's own material 1 mm under the ceiling of a closed furnace, facing down as
// the ceiling does (the Cornell box's lamp, 1 mm under its ceiling): every point anyone can see has
// B = 2 pi W/m^2, the ceiling beside the panel included; the ceiling above it sees only the panel's
// black back 1 mm away, and is covered (coplanar.h, kNearGap). The panel (0.4 m square) is turned
// by 23 degrees so that its outline crosses the ceiling's quadtree leaves. Before the near gap
// counted, those leaves took their irradiance as the mean over all of their area, the dark part
// above the panel included: over the 30 straddling leaves, weighted by the part of each outside the
// panel (found here from the geometry, not from the cover), 0.833 of 2 pi, worst leaf (a quarter
// outside or more) -48 %, the ceiling beside the panel 0.983; now 0.994, 3.0 %, 0.9994.
TEST(Covers, ACeilingBesideAPanelJustUnderItIsAsBrightAsTheRest) {
  const char* json = R"({ "materials": { "g": { "diffuse": [0.5,0.5,0.5], "emission": [1,1,1] } },
  "objects": [ { "type": "box", "material": "g", "min": [0,0,0], "max": [1,1,1], "facing": "inward" },
               { "type": "quad", "material": "g", "vertices": [[0.394045,0.999,0.237753],[0.762247,0.999,0.394045],[0.605955,0.999,0.762247],[0.237753,0.999,0.605955]] } ] })";
  const double kCos = std::cos(23.0 * hr::kPi / 180.0), kSin = std::sin(23.0 * hr::kPi / 180.0);
  auto outside = [&](const testutil::Solved&, const hr::Element& e) {  // the part of a ceiling leaf not above the panel
    int n = 0;
    for (int a = 0; a < 16; ++a)
      for (int b = 0; b < 16; ++b) {
        const hr::Vec3 x = e.poly.sample((a + 0.5) / 16, (b + 0.5) / 16);
        // In the panel's frame: turned back by its 23 degrees about the vertical through (0.5, 0.5).
        const double u = (x.x - 0.5) * kCos + (x.z - 0.5) * kSin, w = -(x.x - 0.5) * kSin + (x.z - 0.5) * kCos;
        n += !(std::abs(u) < 0.2 && std::abs(w) < 0.2);
      }
    return n / 256.0;
  };
  expectFurnaceAroundCover(json, 1e-4, "the panel", [](const hr::Element& e) { return e.normal.y < -0.99 && e.center.y > 0.9995; },
                           outside);
}

// Which parallel patches cover which (coplanar.h): flush, the smaller; with a gap, facing the same
// way, the one in front, whichever is larger, within kNearGap of its size across; never the one in
// front, nor from further away, nor facing the other across a gap (a lamp shining into the ceiling 1 mm above
// it lights it). A long thin strip (a baseboard's face, 5 cm by 2 m) covers only as far as its width
// allows. Each pair is found once, one way (faces in contact: both ways).
TEST(Covers, ANearParallelPatchCoversOnlyFromInFrontAndClose) {
  auto quad = [](double y, double h, bool down) {
    hr::Patch p;
    p.poly.n = 4;
    const hr::Vec3 v[4] = {{-h, y, -h}, {h, y, -h}, {h, y, h}, {-h, y, h}};
    for (int k = 0; k < 4; ++k) p.poly.v[k] = down ? v[k] : v[3 - k];
    p.normal = hr::Vec3(0, down ? -1 : 1, 0);
    p.area = 4 * h * h;
    return p;
  };
  const hr::Patch ceiling = quad(1.0, 1.0, true);
  // Whether `front` covers `back` at their centres' line, and that `back` does not cover `front`
  // (unless they are faces in contact) and the pair is there once.
  auto covers = [](const hr::Patch& back, const hr::Patch& front) {
    std::vector<hr::Patch> patches = {back, front};
    hr::CoplanarCover c(patches, 1e-5);
    const hr::Vec3 onBack(0.0, back.poly.v[0].y, 0.0), onFront(0.0, front.poly.v[0].y, 0.0);
    const bool yes = c.coverOf(0, onBack) == 1;
    const bool contact = glm::dot(back.normal, front.normal) < 0.0;
    EXPECT_EQ(c.coverOf(1, onFront) == 0, yes && contact) << "the other way";
    EXPECT_EQ(c.pairs(), yes ? (contact ? 2u : 1u) : 0u);
    return yes;
  };
  // The panel's size across (2 A / perimeter) is 0.2 m, so kNearGap allows 2 mm.
  EXPECT_TRUE(covers(ceiling, quad(1.0, 0.2, true))) << "flush";
  EXPECT_TRUE(covers(ceiling, quad(0.999, 0.2, true))) << "1 mm in front";
  EXPECT_TRUE(covers(ceiling, quad(0.9981, 0.2, true))) << "1.9 mm in front";
  EXPECT_FALSE(covers(ceiling, quad(0.9975, 0.2, true))) << "2.5 mm in front: light reaches under it";
  EXPECT_TRUE(covers(quad(1.001, 0.2, true), ceiling)) << "a panel 1 mm behind is covered by the ceiling, not it";
  EXPECT_FALSE(covers(ceiling, quad(0.999, 0.2, false))) << "facing the ceiling 1 mm under it";
  EXPECT_TRUE(covers(ceiling, quad(1.0, 0.2, false))) << "faces in contact";
  EXPECT_TRUE(covers(quad(1.0, 0.1, true), quad(0.999, 0.25, true))) << "a lamp 1 mm under a smaller ceiling tile";
  hr::Patch turned = quad(1.0, 0.2, false);
  turned.normal.x = -6e-17;  // as a transform leaves an axis-aligned normal
  EXPECT_TRUE(covers(ceiling, turned)) << "faces in contact, one normal off its axis by -6e-17";
  auto strip = [&](double y) {
    hr::Patch p = quad(y, 0.025, true);                   // 5 cm wide...
    for (int k = 0; k < p.poly.n; ++k) p.poly.v[k].x *= 40.0;  // ...and 2 m long: radius 1 m, size across 4.9 cm
    p.area *= 40.0;
    return p;
  };
  EXPECT_TRUE(covers(ceiling, strip(0.9997))) << "a strip 5 cm wide, 0.3 mm in front";
  EXPECT_FALSE(covers(ceiling, strip(0.995))) << "a strip 5 cm wide, 5 mm in front";
}

}  // namespace
