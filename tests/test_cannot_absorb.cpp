// A closed scene that cannot absorb (every surface its light reaches has rho = 1) has no finite
// solution: it is refused early and by name, exit 2 (issue 10, item 2; absorption.cpp). The white
// rooms at rho 0.99 and 0.999 that must converge are in test_solver_analytic.cpp (Furnace).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <fstream>

#include "helpers.h"
#include "test_dir.h"

namespace {

TEST(CannotAbsorb, Rho1IsRefusedBeforeSolving) {
  auto t0 = std::chrono::steady_clock::now();
  try {
    testutil::solveText(testutil::furnace(1.0), hr::SolverOptions{});
    FAIL() << "a closed room that cannot absorb has no finite solution";
  } catch (const hr::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot absorb"), std::string::npos) << e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 20.0) << "early: 262 k walk steps, no solve";
}

TEST(CannotAbsorb, Rho1ExitsTwoFromTheCommandLine) {
  auto dir = testutil::testDir();
  std::ofstream(dir / "white.json") << testutil::furnace(1.0);
  std::string text;
  int status = testutil::runCli("solve " + (dir / "white.json").string() + " -o " + (dir / "out").string() + " --quiet", text);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2) << text;
  EXPECT_NE(text.find("cannot absorb"), std::string::npos) << text;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "stats.json")) << "nothing written";
}

// Light that can get lost makes a finite answer: white surfaces with an opening, or a white room
// with one grey face, are solved; a white box sealed around the lamp inside a grey room is not.
TEST(CannotAbsorb, OnlyScenesThatCannotAbsorbAreRefused) {
  const char* open = R"({ "materials": { "w": { "diffuse": [1,1,1] }, "l": { "diffuse": [1,1,1], "emission": [1,1,1] } },
  "objects": [
    { "type": "quad", "material": "w", "vertices": [[0,0,0],[1,0,0],[1,0,1],[0,0,1]] },
    { "type": "quad", "material": "l", "vertices": [[0,1,0],[0,1,1],[1,1,1],[1,1,0]] } ] })";
  hr::SolverOptions o;
  o.eps = 1e-3;
  EXPECT_NO_THROW(testutil::solveText(open, o));
  const char* oneGrey = R"({ "materials": { "w": { "diffuse": [1,1,1], "emission": [1,1,1] }, "g": { "diffuse": [0.5,0.5,0.5] } },
  "objects": [ { "type": "box", "material": "w", "min": [0,0,0], "max": [1,1,1], "facing": "inward" },
    { "type": "quad", "material": "g", "vertices": [[0.25,0.001,0.25],[0.25,0.001,0.75],[0.75,0.001,0.75],[0.75,0.001,0.25]] } ] })";
  EXPECT_NO_THROW(testutil::solveText(oneGrey, o));
  const char* sealed = R"({ "materials": { "w": { "diffuse": [1,1,1], "emission": [1,1,1] }, "g": { "diffuse": [0.5,0.5,0.5] } },
  "objects": [ { "type": "box", "material": "g", "min": [-1,-1,-1], "max": [2,2,2], "facing": "inward" },
    { "type": "box", "material": "w", "min": [0,0,0], "max": [1,1,1], "facing": "inward" } ] })";
  EXPECT_THROW(testutil::solveText(sealed, o), hr::InputError);
}

}  // namespace
