// Whole runs of the VISION-like host: the Cornell box's energy balance (emitted = absorbed +
// escaped within 1 %, on both hosts; escaped light measured by the audit's rays against the exact
// surfaces, independently of the shooting), 1 vs 2 threads bit-identical, and the command line
// (--host vision writes the same outputs, `render` reads its solution; unknown hosts exit 2).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../helpers.h"
#include "../test_dir.h"
#include "vision_helpers.h"

namespace {

void checkBalance(const hr::SolveStats& st, const char* host) {
  ASSERT_TRUE(st.converged) << host;
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR((st.absorbedW[c] + st.escapedW[c]) / st.emittedW[c], 1.0, 0.01) << host << " channel " << c;
    EXPECT_GT(st.escapedW[c], 0.1 * st.emittedW[c]) << host << ": the box is open at the front";
  }
  std::printf("%s: emitted %.4f W, absorbed %.4f, escaped %.4f, imbalance %.3f %% (green)\n", host, st.emittedW.y,
              st.absorbedW.y, st.escapedW.y, 100.0 * (st.emittedW.y - st.absorbedW.y - st.escapedW.y) / st.emittedW.y);
}

TEST(VisionRuns, CornellBalanceOnBothHosts) {
  hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(hr::kDefaultSceneJson, "").settings);
  auto v = visiontest::solveText(hr::kDefaultSceneJson, o);
  checkBalance(v.stats, "vision");
  EXPECT_EQ(v.stats.links, 0u);
  EXPECT_GT(v.stats.linksComputed, 0u);
  auto b = testutil::solveText(hr::kDefaultSceneJson, o);
  checkBalance(b.stats, "bright");
}

/// Every leaf's radiosity, in tree order, as bytes.
std::vector<double> leafValues(const visiontest::Solved& s) {
  std::vector<double> out;
  for (const vision::Element* e : s.leaves()) out.insert(out.end(), {e->B.x, e->B.y, e->B.z, e->rect.u0, e->rect.v0});
  return out;
}

TEST(VisionRuns, OneAndTwoThreadsBitIdentical) {
  // A scene with curved and flat surfaces, clusters and shadows: the Cornell box with a sphere.
  std::string json = hr::kDefaultSceneJson;
  const std::string marker = R"("objects": [)";
  json.insert(json.find(marker) + marker.size(),
              R"({ "type": "sphere", "material": "white", "center": [1.6, 0.16, 0.4], "radius": 0.15 },)");
  hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(json, "").settings);
  o.eps = 2e-3;  // determinism does not need a fine answer; the default threshold took 5 minutes
  std::vector<double> r[2];
  hr::SolveStats st[2];
  for (int t = 1; t <= 2; ++t) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t));
    auto s = visiontest::solveText(json, o);
    r[t - 1] = leafValues(s);
    st[t - 1] = s.stats;
  }
  ASSERT_EQ(r[0].size(), r[1].size());
  EXPECT_EQ(std::memcmp(r[0].data(), r[1].data(), r[0].size() * sizeof(double)), 0) << "leaf radiosity bit for bit";
  EXPECT_EQ(st[0].rays, st[1].rays);
  EXPECT_EQ(st[0].linksComputed, st[1].linksComputed);
  EXPECT_EQ(std::memcmp(&st[0].absorbedW, &st[1].absorbedW, sizeof(hr::Rgb)), 0);
  EXPECT_GE(st[1].refine.threads, 2) << "the two-thread run did use two threads";
}

TEST(VisionCli, SolveWritesTheOutputsAndRenderReadsThem) {
  namespace fs = std::filesystem;
  const fs::path dir = testutil::testDir() / "out";
  std::string out;
  ASSERT_EQ(testutil::runCli("solve --host vision --quiet -o " + dir.string(), out), 0) << out;
  for (const char* f : {"stats.json", "solution.vtp", "solution.ghrs", "front.exr", "front.png"})
    EXPECT_TRUE(fs::exists(dir / f)) << f << "\n" << out;
  std::ifstream in(dir / "stats.json");
  nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["host"], "vision");
  EXPECT_EQ(j["counts"]["links"], 0);
  EXPECT_GT(j["counts"]["links_computed"].get<double>(), 0.0);
  ASSERT_EQ(testutil::runCli("render " + (dir / "solution.ghrs").string() + " -o " + (dir / "again.png").string() + " --quiet", out), 0)
      << out;
  EXPECT_TRUE(fs::exists(dir / "again.png"));
}

TEST(VisionCli, UnknownHostExits2ListingTheValidOnes) {
  std::string out;
  int rc = testutil::runCli("solve --host nope --quiet -o /nonexistent/never", out);
  EXPECT_EQ(WEXITSTATUS(rc), 2) << out;
  EXPECT_NE(out.find("valid: bright, vision"), std::string::npos) << out;
}

}  // namespace
