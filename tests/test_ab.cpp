// `glossyhr ab` through the real command line: the diffuse-only run holds the same energy (its
// audit balances within 1 %: the specular share is not silently absorbed), both images, the
// difference and the stats appear together; a scene with nothing glossy is refused with nothing
// written.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "helpers.h"
#include "test_dir.h"

namespace fs = std::filesystem;

TEST(AbCli, DiffuseOnlyRunBalancesAndTheGlossyRunMovesLight) {
  fs::path dir = testutil::testDir() / "ab";
  std::string out;
  int rc = testutil::runCli("ab " + std::string(GHR_SOURCE_DIR) + "/scenes/three_lights.json -o " + dir.string(), out);
  ASSERT_EQ(rc, 0) << out;
  for (const char* f : {"ab.json", "diffuse_stats.json", "glossy_stats.json", "overview_diffuse.exr", "overview_glossy.exr",
                        "overview_side_by_side.png", "overview_difference.png"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  std::ifstream in(dir / "ab.json");
  nlohmann::json ab = nlohmann::json::parse(in);
  EXPECT_EQ(ab["glossy_materials_made_lambertian"].get<int>(), 1);
  for (const char* run : {"diffuse", "glossy"}) {
    const auto& r = ab[run];
    double emitted = r["emitted_w"], absorbed = r["absorbed_w"], escaped = r["escaped_w"];
    EXPECT_NEAR(absorbed + escaped, emitted, 0.01 * emitted) << run;
  }
  // The reflector's specular share goes to the wall as spots instead of spreading diffusely: the
  // wall is brighter in the glossy run, the reflector itself darker toward the camera.
  const auto& objects = ab["cameras"]["overview"]["objects_by_change"];
  ASSERT_GE(objects.size(), 3u);
  EXPECT_EQ(objects[0]["material"], "wall");
  EXPECT_GT(objects[0]["change_pct"].get<double>(), 1.0);
}

TEST(AbCli, SceneWithoutGlossIsRefusedWithNothingWritten) {
  fs::path dir = testutil::testDir() / "ab";
  std::string out;
  int rc = testutil::runCli("ab " + std::string(GHR_SOURCE_DIR) + "/scenes/cornell_box.json -o " + dir.string(), out);
  EXPECT_EQ(WEXITSTATUS(rc), 2) << out;
  EXPECT_NE(out.find("cornell_box.json: no glossy material"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir));
}
