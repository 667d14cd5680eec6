// Analytic scenes: form factors read from one-bounce solves, the closed-cube furnace, and energy
// conservation of open scenes (escaped power measured independently by ray casting).
#include <gtest/gtest.h>
#include <hr/kernel.h>

#include "helpers.h"

namespace {

const char* kParallel = R"({
  "materials": { "e": { "emission": [1,1,1] }, "r": { "diffuse": [0.8,0.8,0.8] } },
  "objects": [
    { "type": "quad", "material": "e", "vertices": [[0,0,1],[0,1,1],[1,1,1],[1,0,1]] },
    { "type": "quad", "material": "r", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]] } ] })";

const char* kPerpendicular = R"({
  "materials": { "e": { "emission": [1,1,1] }, "r": { "diffuse": [0.8,0.8,0.8] } },
  "objects": [
    { "type": "quad", "material": "e", "vertices": [[0,0,0],[0,1,0],[0,1,1],[0,0,1]] },
    { "type": "quad", "material": "r", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]] } ] })";

hr::SolverOptions oneBounce() {
  hr::SolverOptions o;
  o.eps = 1e-5;
  o.maxLevel = 6;
  o.raysPerLink = 4;
  return o;
}

TEST(FormFactorSolve, ParallelUnitSquaresAtDistanceOne) {
  // Receiver B = rho * F * pi * Le with F = 0.199825 (closed form), to 1 %.
  auto s = testutil::solveText(kParallel, oneBounce());
  double F = hr::parallelSquaresFormFactor(1.0, 1.0);
  ASSERT_NEAR(F, 0.199825, 1e-6);
  double B = s.meanRadiosity(1).y;
  EXPECT_NEAR(B / (0.8 * F * hr::kPi), 1.0, 0.01);
}

TEST(FormFactorSolve, PerpendicularSquaresSharingAnEdge) {
  auto s = testutil::solveText(kPerpendicular, oneBounce());
  double F = hr::perpendicularSquaresFormFactor();
  ASSERT_NEAR(F, 0.200044, 1e-6);
  double B = s.meanRadiosity(1).y;
  EXPECT_NEAR(B / (0.8 * F * hr::kPi), 1.0, 0.01);
}

}  // namespace
