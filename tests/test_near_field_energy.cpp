// Energy is never lost or created (issue 10, item 1): the scenes the issue measured, each balanced
// (emitted = absorbed + escaped, both measured by the independent audit) within 1 % at the default
// threshold, and within 3 % at any threshold from 1e-4 to 1.
#include <gtest/gtest.h>

#include <stdexcept>

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
