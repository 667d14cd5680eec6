// Honest reporting (issue 10, item 3): the independent energy audit decides whether an answer is
// trustworthy. Beyond --max-imbalance (default 2 % of the emitted power, plus 3 of the audit's
// standard errors) the summary says so, stats.json has "energy_ok": false and the exit code is 3.
// The check is seen to fail: a test-only switch that lets every shadow ray through gives a wrong
// answer on purpose, and the audit, which traces its own rays, must catch it.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>

#include "helpers.h"
#include "test_dir.h"

namespace {

// A lamp 1 m above a floor, a plate half-way between them (its black back faces the lamp): nearly
// all the light ends on the plate's back. With shadow rays unblocked the floor is lit as if the plate
// were not there, and absorbs light that never reached it.
const char* kShadowedFloor = R"({
  "materials": { "f": { "diffuse": [0.5,0.5,0.5] }, "l": { "emission": [1,1,1] } },
  "objects": [
    { "type": "quad", "material": "f", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]] },
    { "type": "quad", "material": "f", "vertices": [[-0.5,0.5,-0.5],[-0.5,0.5,0.5],[0.5,0.5,0.5],[0.5,0.5,-0.5]] },
    { "type": "quad", "material": "l", "vertices": [[-0.25,1,-0.25],[0.25,1,-0.25],[0.25,1,0.25],[-0.25,1,0.25]] } ] })";

struct CliRun {
  int exit = -1;
  std::string text;
  nlohmann::json stats;
};

CliRun solveCli(const std::string& scene, const std::string& flags) {
  auto dir = testutil::testDir();
  std::ofstream(dir / "scene.json") << scene;
  CliRun r;
  int status = testutil::runCli("solve " + (dir / "scene.json").string() + " -o " + (dir / "out").string() + " " + flags, r.text);
  if (WIFEXITED(status)) r.exit = WEXITSTATUS(status);
  std::ifstream in(dir / "out" / "stats.json");
  if (in) r.stats = nlohmann::json::parse(in);
  return r;
}

TEST(EnergyReport, HonestAnswerExitsZeroWithEnergyOk) {
  CliRun r = solveCli(kShadowedFloor, "--quiet");
  EXPECT_EQ(r.exit, 0) << r.text;
  ASSERT_TRUE(r.stats.contains("energy_ok")) << r.text;
  EXPECT_TRUE(r.stats["energy_ok"].get<bool>());
  EXPECT_DOUBLE_EQ(r.stats["max_imbalance"].get<double>(), 0.02);
}

TEST(EnergyReport, WrongAnswerFailsTheAuditWithExitThree) {
  ASSERT_EQ(setenv("GLOSSYHR_TEST_ONLY_UNBLOCKED_SHADOW_RAYS", "1", 1), 0);
  CliRun r = solveCli(kShadowedFloor, "--quiet");
  unsetenv("GLOSSYHR_TEST_ONLY_UNBLOCKED_SHADOW_RAYS");
  EXPECT_EQ(r.exit, 3) << r.text;
  EXPECT_NE(r.text.find("ENERGY CHECK FAILED"), std::string::npos) << r.text;
  ASSERT_TRUE(r.stats.contains("energy_ok")) << r.text;
  EXPECT_FALSE(r.stats["energy_ok"].get<bool>());
  EXPECT_TRUE(r.stats["converged"].get<bool>()) << "converged, yet not trustworthy: only the audit sees it";
  const auto& e = r.stats["energy"];
  const double imbalance = e["imbalance_w"][1].get<double>(), emitted = e["emitted_w"][1].get<double>();
  EXPECT_GT(std::abs(imbalance), 0.1 * emitted) << "the wrong answer is far off";
}

TEST(EnergyReport, MaxImbalanceIsTheThreshold) {
  // The same wrong answer passes when the threshold allows everything (1 = the whole emitted power).
  ASSERT_EQ(setenv("GLOSSYHR_TEST_ONLY_UNBLOCKED_SHADOW_RAYS", "1", 1), 0);
  CliRun loose = solveCli(kShadowedFloor, "--quiet --max-imbalance 1");
  unsetenv("GLOSSYHR_TEST_ONLY_UNBLOCKED_SHADOW_RAYS");
  EXPECT_EQ(loose.exit, 0) << loose.text;
  EXPECT_TRUE(loose.stats["energy_ok"].get<bool>());
  EXPECT_DOUBLE_EQ(loose.stats["max_imbalance"].get<double>(), 1.0);
}

TEST(EnergyReport, LibraryFlagsTheWrongAnswer) {
  hr::SolverOptions o;
  o.eps = 1e-3;
  auto good = testutil::solveText(kShadowedFloor, o);
  EXPECT_TRUE(good.stats.energyOk);
  o.testOnlyUnblockedShadowRays = true;
  auto bad = testutil::solveText(kShadowedFloor, o);
  EXPECT_FALSE(bad.stats.energyOk);
  for (int c = 0; c < 3; ++c) EXPECT_GT(bad.stats.allowedImbalanceW[c], 0.0);
}

}  // namespace
