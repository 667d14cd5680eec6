// --basis auto end to end, through the command line: a scene with a broad (n = 10) and a sharp
// (n = 1000) glossy floor gets spherical harmonics for one and Haar for the other in one solve, says so
// in the summary and in stats.json, keeps its energy within 1 %, and its solution file loads and saves
// back to the same bytes and renders again.
#include <gtest/gtest.h>
#include <hr/solution.h>
#include <hr/solution_view.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "helpers.h"
#include "registry.h"
#include "test_dir.h"
#include "saved_bytes.h"

namespace {

const char* kTwoFloors = R"({
  "materials": {
    "lamp": { "emission": [6, 6, 6] },
    "wall": { "diffuse": [0.6, 0.6, 0.6] },
    "broad": { "diffuse": [0.2, 0.2, 0.2], "specular": [0.5, 0.5, 0.5], "exponent": 10 },
    "sharp": { "diffuse": [0.1, 0.1, 0.1], "specular": [0.7, 0.7, 0.7], "exponent": 1000 }
  },
  "objects": [
    { "type": "quad", "material": "lamp", "vertices": [[-0.3,1.5,-0.3],[0.3,1.5,-0.3],[0.3,1.5,0.3],[-0.3,1.5,0.3]] },
    { "type": "quad", "material": "broad", "vertices": [[-2,0,-2],[-2,0,2],[0,0,2],[0,0,-2]] },
    { "type": "quad", "material": "sharp", "vertices": [[0,0,-2],[0,0,2],[2,0,2],[2,0,-2]] },
    { "type": "quad", "material": "wall", "vertices": [[-2,0,-2],[2,0,-2],[2,2,-2],[-2,2,-2]] }
  ],
  "cameras": [ { "name": "c", "eye": [0, 1.2, 3.5], "look_at": [0, 0.3, 0], "up": [0, 1, 0], "fov_y_deg": 50, "width": 64, "height": 48 } ]
})";

std::string readAll(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(BasisAuto, AMixedSceneSolvesBalancedAndItsFileRoundTrips) {
  const auto dir = testutil::testDir();
  std::ofstream(dir / "scene.json") << kTwoFloors;
  std::string text;
  int status = testutil::runCli("solve " + (dir / "scene.json").string() + " -o " + (dir / "out").string() +
                                    " --algorithm is --basis auto --eps 1e-3",
                                text);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << text;
  nlohmann::json stats = nlohmann::json::parse(readAll(dir / "out" / "stats.json"));

  // The choice per material, in stats.json and in the run summary.
  const auto& ext = stats["extension"];
  std::string broad, sharp;
  for (const auto& [key, value] : ext.items()) {
    if (key.starts_with("basis_material_") && key.ends_with("_broad")) broad = value.get<std::string>();
    if (key.starts_with("basis_material_") && key.ends_with("_sharp")) sharp = value.get<std::string>();
  }
  EXPECT_TRUE(broad.starts_with("sh (auto")) << broad;
  EXPECT_TRUE(sharp.starts_with("haar (auto")) << sharp;
  EXPECT_NE(text.find("_broad = sh (auto"), std::string::npos) << text;
  EXPECT_NE(text.find("_sharp = haar (auto"), std::string::npos) << text;
  EXPECT_GE(ext["distribution_parts_in_other_bases"].get<double>(), 1.0) << "a cluster above both floors mixes bases";

  // Energy: emitted = absorbed + escaped within 1 %, per channel.
  const auto& e = stats["energy"];
  for (int c = 0; c < 3; ++c) {
    double emitted = e["emitted_w"][c].get<double>(), imbalance = e["imbalance_w"][c].get<double>();
    EXPECT_LT(std::abs(imbalance), 0.01 * emitted) << "channel " << c;
  }

  // The file: loaded over its own elements, the extension's section saves back to the same bytes.
  hr::Solution loaded = hr::loadSolution((dir / "out" / "solution.ghrs").string());
  hr::SolutionView view(loaded);
  auto back = adapters::findExtension(loaded.extension.name).make();
  ASSERT_EQ(back->formatVersion(), loaded.extension.version);
  back->load(loaded.extension.bytes, view);
  EXPECT_EQ(testutil::savedBytes(*back), loaded.extension.bytes);

  // And it renders again, from its own camera.
  status = testutil::runCli("render " + (dir / "out" / "solution.ghrs").string() + " --quiet -o " + (dir / "again.exr").string(), text);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << text;
  EXPECT_TRUE(std::filesystem::exists(dir / "again.exr"));
}

}  // namespace
