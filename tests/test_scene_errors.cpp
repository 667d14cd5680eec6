// Bad input, table-driven, through the real command line: each case must exit non-zero, name the
// file and the key or line, and leave no output folder behind.
#include <gtest/gtest.h>
#include <hr/scene.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "helpers.h"
#include "test_dir.h"

namespace fs = std::filesystem;

namespace {

struct Case {
  const char* name;
  std::string scene;      // JSON text
  const char* expect;     // substring of the error message
  const char* meshName = nullptr;
  std::string mesh;       // optional mesh file written beside the scene
};

std::string wrap(const std::string& materials, const std::string& objects) {
  return R"({ "materials": {)" + materials + R"(}, "objects": [)" + objects + "] }";
}
const std::string kLight = R"("l": { "emission": [1,1,1] }, "w": { "diffuse": [0.5,0.5,0.5] })";
const std::string kQuad = R"({ "type": "quad", "material": "l", "vertices": [[0,0,1],[0,1,1],[1,1,1],[1,0,1]] })";

std::vector<Case> cases() {
  return {
      {"malformed_json", "{ \"materials\": {\n  \"a\": [1,2,\n", "line 3", nullptr, ""},
      {"unknown_object_type", wrap(kLight, kQuad + R"(, { "type": "torus", "material": "w" })"), "objects[1].type", nullptr, ""},
      {"unknown_material", wrap(kLight, kQuad + R"(, { "type": "sphere", "material": "nope", "center": [0,0,0], "radius": 1 })"), "unknown material \"nope\"", nullptr, ""},
      {"missing_material", wrap(kLight, kQuad + R"(, { "type": "sphere", "center": [0,0,0], "radius": 1 })"), "objects[1]: missing required key \"material\"", nullptr, ""},
      {"non_numeric_coordinate", wrap(kLight, R"({ "type": "quad", "material": "l", "vertices": [[0,0,1],[0,"x",1],[1,1,1],[1,0,1]] })"), "objects[0].vertices[1][1]", nullptr, ""},
      {"nan_coordinate", wrap(kLight, R"({ "type": "sphere", "material": "l", "center": [0,0,NaN], "radius": 1 })"), "line", nullptr, ""},
      {"negative_reflectance", wrap(R"("l": { "emission": [1,1,1], "diffuse": [0.5,-0.1,0.5] })", kQuad), "materials.l.diffuse", nullptr, ""},
      {"energy_gaining", wrap(R"("l": { "emission": [1,1,1], "diffuse": [0.6,0.6,0.6], "specular": [0.5,0.5,0.5] })", kQuad), "> 1", nullptr, ""},
      {"negative_emission", wrap(R"("l": { "emission": [1,-1,1] })", kQuad), "materials.l.emission", nullptr, ""},
      {"zero_radius", wrap(kLight, kQuad + R"(, { "type": "sphere", "material": "w", "center": [0,0,0], "radius": 0 })"), "objects[1].radius", nullptr, ""},
      {"zero_size_box", wrap(kLight, kQuad + R"(, { "type": "box", "material": "w", "min": [0,0,0], "max": [1,0,1] })"), "zero-size box", nullptr, ""},
      {"zero_area_quad", wrap(kLight, R"({ "type": "quad", "material": "l", "vertices": [[0,0,0],[1,0,0],[2,0,0],[3,0,0]] })"), "zero area", nullptr, ""},
      {"no_emitter", wrap(R"("w": { "diffuse": [0.5,0.5,0.5] })", R"({ "type": "sphere", "material": "w", "center": [0,0,0], "radius": 1 })"), "no emitting surface", nullptr, ""},
      {"missing_mesh", wrap(kLight, kQuad + R"(, { "type": "mesh", "material": "w", "file": "nothere.obj" })"), "nothere.obj", nullptr, ""},
      {"mesh_index_out_of_range", wrap(kLight, kQuad + R"(, { "type": "mesh", "material": "w", "file": "bad.obj" })"), "bad.obj",
       "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"},
      {"mesh_nan_vertex", wrap(kLight, kQuad + R"(, { "type": "mesh", "material": "w", "file": "nan.obj" })"), "non-finite",
       "nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
      {"malformed_ply", wrap(kLight, kQuad + R"(, { "type": "mesh", "material": "w", "file": "bad.ply" })"), "bad.ply",
       "bad.ply", "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n0 0\n"},
  };
}

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class SceneErrors : public ::testing::TestWithParam<Case> {};

TEST_P(SceneErrors, ClearMessageNonZeroExitNoOutput) {
  const Case& c = GetParam();
  fs::path dir = testutil::testDir();
  fs::path scene = dir / "scene.json";
  std::ofstream(scene) << c.scene;
  if (c.meshName) std::ofstream(dir / c.meshName) << c.mesh;
  fs::path out = dir / "out";
  std::string text;
  int status = testutil::runCli("solve " + scene.string() + " -o " + out.string() + " --quiet", text);
  EXPECT_NE(status, 0) << text;
  EXPECT_NE(text.find(scene.string()), std::string::npos) << "message names the file: " << text;
  EXPECT_NE(text.find(c.expect), std::string::npos) << "message names the key: " << text;
  EXPECT_FALSE(fs::exists(out)) << "no output may be written";
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Table, SceneErrors, ::testing::ValuesIn(cases()),
                         [](const auto& tp) { return std::string(tp.param.name); });

TEST(SceneWarnings, UnknownKeysAreReportedNotFatal) {
  hr::Scene s = hr::parseScene(wrap(kLight, R"({ "type": "quad", "material": "l", "colour": 3, "vertices": [[0,0,1],[0,1,1],[1,1,1],[1,0,1]] })"), "x.json");
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("objects[0]: unknown key \"colour\""), std::string::npos);
}

}  // namespace
