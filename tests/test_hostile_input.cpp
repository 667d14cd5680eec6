// Hostile input, table-driven through the real command line, one or more cases for every class of
// issue 12 (crashes, hangs and unbounded memory, non-finite values, wrong exit codes, silent
// defaults, partial output, misleading results). Every case must exit 2, name the file and the key or
// line (or the flag), keep its message short, and leave the output folder exactly as it was: it is
// filled with a previous run's files first, and compared byte for byte afterwards.
#include <gtest/gtest.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "helpers.h"
#include "test_dir.h"

namespace fs = std::filesystem;

namespace {

struct File {
  std::string name;     // relative to the test folder; "x/" makes a folder
  std::string content;  // "<fifo>", "<link:TARGET>", "<exr:grey|black|inf>" are made specially
};

struct Case {
  const char* cls;   // the issue's class
  const char* name;
  std::vector<File> files;
  std::string args;                 // {dir}: the test folder, {out}: the output folder
  std::vector<std::string> expect;  // substrings of the output ({dir} replaced)
};

const std::string kMats = R"("l": { "emission": [1,1,1] }, "w": { "diffuse": [0.5,0.5,0.5] })";
const std::string kLamp = R"({ "type": "quad", "material": "l", "vertices": [[0,0,1],[0,1,1],[1,1,1],[1,0,1]] })";

std::string scene(const std::string& objects, const std::string& extra = "", const std::string& mats = kMats) {
  return R"({ "materials": { )" + mats + R"( }, "objects": [ )" + objects + " ]" + extra + " }";
}
std::string withLamp(const std::string& object) { return scene(kLamp + ", " + object); }
std::string mesh(const std::string& file) { return withLamp(R"({ "type": "mesh", "material": "w", "file": ")" + file + R"(" })"); }
std::string mgfObject(const std::string& file) { return withLamp(R"({ "type": "mgf", "file": ")" + file + R"(" })"); }
const std::string kMgfLamp = "m lamp =\n ed 100\nv a =\n p 0 0 0\nv b =\n p 1 0 0\nv c =\n p 0 1 0\nf a b c\n";

std::vector<Case> cases() {
  const std::string solve = "solve {dir}/s.json -o {out} --quiet";
  std::vector<Case> c = {
      // ---- crashes ---------------------------------------------------------------------------------
      {"crash", "empty_material_name_solve",
       {{"s.json", scene(R"({ "type": "quad", "material": "", "vertices": [[0,0,1],[0,1,1],[1,1,1],[1,0,1]] })", "",
                         R"("": { "emission": [1,1,1] })")}},
       solve, {"{dir}/s.json", "materials", "must not be empty"}},
      {"crash", "empty_material_name_info",
       {{"s.json", scene(kLamp + R"(, { "type": "quad", "material": "", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]] })")}},
       "info {dir}/s.json", {"{dir}/s.json", "objects[1].material", "unknown material \"\""}},
      {"crash", "translate_1e20",
       {{"s.json", withLamp(R"({ "type": "sphere", "material": "w", "center": [0,0,0], "radius": 1, "transform": { "translate": [1e20,0,0] } })")}},
       solve, {"{dir}/s.json", "objects[1].transform.translate[0]", "outside the allowed range"}},
      {"crash", "scale_lands_far_away",
       {{"s.json", withLamp(R"({ "type": "sphere", "material": "w", "center": [10,0,0], "radius": 1, "transform": { "scale": 1e6 } })")}},
       solve, {"{dir}/s.json", "objects[1]", "a vertex lands at coordinate"}},
      {"crash", "obj_vertex_1e20", {{"s.json", mesh("big.obj")}, {"big.obj", "v 1e20 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}},
       solve, {"{dir}/big.obj", "vertex 1", "outside"}},
      {"crash", "mgf_sphere_radius_1e20", {{"s.json", mgfObject("big.mgf")}, {"big.mgf", kMgfLamp + "v o =\n p 0 0 0\nsph o 1e20\n"}},
       solve, {"{dir}/big.mgf", "line 12", "sph"}},
      {"crash", "camera_eye_1e20",
       {{"s.json", scene(kLamp, R"(, "cameras": [ { "name": "c", "eye": [1e20,0,0], "look_at": [0,0,0] } ])")}},
       solve, {"{dir}/s.json", "cameras[0].eye[0]"}},
      // ---- hangs and unbounded memory ------------------------------------------------------------------
      {"hang", "ply_header_stops_after_format", {{"s.json", mesh("h.ply")}, {"h.ply", "ply\nformat ascii 1.0\n"}},
       solve, {"{dir}/h.ply", "end_header"}},
      {"hang", "mesh_is_dev_zero", {{"s.json", mesh("zero.obj")}, {"zero.obj", "<link:/dev/zero>"}},
       solve, {"{dir}/zero.obj", "character device"}},
      {"hang", "scene_is_dev_zero", {{"zero.json", "<link:/dev/zero>"}}, "info {dir}/zero.json",
       {"{dir}/zero.json", "character device"}},
      {"hang", "mgf_object_is_dev_zero", {{"s.json", mgfObject("zero.mgf")}, {"zero.mgf", "<link:/dev/zero>"}},
       solve, {"{dir}/zero.mgf", "objects[1]", "character device"}},
      {"hang", "mesh_is_fifo", {{"s.json", mesh("f.obj")}, {"f.obj", "<fifo>"}}, solve, {"{dir}/f.obj", "FIFO"}},
      {"hang", "mgf_array_of_1e8", {{"a.mgf", kMgfLamp + "xf -a 100000000 -t 1 0 0\nf a b c\nxf\n"}},
       "solve {dir}/a.mgf -o {out} --quiet", {"{dir}/a.mgf", "line 10", "count"}},
      {"hang", "mgf_nested_arrays_beyond_work_limit",
       {{"a.mgf", kMgfLamp + "xf -a 100000 -t 1 0 0\nxf -a 100000 -t 0 1 0\nf a b c\nxf\nxf\n"}},
       "solve {dir}/a.mgf -o {out} --quiet", {"{dir}/a.mgf: line 1", "entity evaluations"}},
      {"hang", "mgf_face_too_large", {{"a.mgf", kMgfLamp + "f" + [] {
                                         std::string s;
                                         for (int i = 0; i < 5000; ++i) s += i % 2 ? " a" : " b";
                                         return s;
                                       }() + "\n"}},
       "info {dir}/a.mgf", {"{dir}/a.mgf", "line 10", "5000 vertices"}},
      // ---- non-finite values out -----------------------------------------------------------------------
      {"nonfinite", "emission_1e39", {{"s.json", scene(kLamp, "", R"("l": { "emission": [1e39,1,1] })")}},
       solve, {"{dir}/s.json", "materials.l.emission[0]"}},
      {"nonfinite", "mgf_ed_1e300", {{"a.mgf", "m hot =\n ed 1e300\nv a =\n p 0 0 0\nv b =\n p 1 0 0\nv c =\n p 0 1 0\nf a b c\n"}},
       "solve {dir}/a.mgf -o {out} --quiet", {"{dir}/a.mgf", "line 2", "ed"}},
      {"nonfinite", "mgf_cxy_denormal", {{"a.mgf", "c x =\n cxy 0.376563 5e-324\n" + kMgfLamp}},
       "info {dir}/a.mgf", {"{dir}/a.mgf", "line 2", "cxy", "chromaticity"}},
      // ---- wrong exit codes and unnamed errors -----------------------------------------------------------
      {"exitcode", "json_number_1e400", {{"s.json", "{\n \"materials\": {},\n \"objects\": [1e400]\n}\n"}}, solve,
       {"{dir}/s.json", "line 3", "out of range"}},
      {"exitcode", "emission_1e50", {{"s.json", mesh("m.obj")}, {"m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl hot\nf 1 2 3\n"},
                                      {"m.mtl", "newmtl hot\nKe 1e50 1 1\n"}},
       solve, {"{dir}/m.obj", "\"hot\"", "Ke"}},
      {"exitcode", "settings_eps_1e300", {{"s.json", scene(kLamp, R"(, "settings": { "eps": 1e300 })")}}, solve,
       {"{dir}/s.json", "settings.eps"}},
      {"exitcode", "ply_declares_4e9_vertices",
       {{"s.json", mesh("v.ply")}, {"v.ply", "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
                                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n"}},
       solve, {"{dir}/v.ply", "vertex"}},
      {"exitcode", "cli_unknown_option", {}, "solve --bogus", {"--bogus"}},
      {"exitcode", "cli_not_a_number", {}, "solve --eps abc -o {out}", {"--eps"}},
      {"exitcode", "cli_missing_value", {}, "render", {"solution"}},
      // ---- silent defaults ------------------------------------------------------------------------------
      {"default", "duplicate_json_key", {{"s.json", scene(kLamp, R"(, "settings": { "eps": 1e-3, "eps": 1e-2 })")}}, solve,
       {"{dir}/s.json", "settings.eps", "duplicate key"}},
      {"default", "mgf_object_is_a_directory", {{"s.json", mgfObject("d.mgf")}, {"d.mgf/", ""}}, solve,
       {"{dir}/d.mgf", "objects[1]", "directory"}},
      {"default", "mgf_object_is_empty", {{"s.json", mgfObject("e.mgf")}, {"e.mgf", ""}}, solve,
       {"{dir}/e.mgf", "objects[1].file", "no geometry"}},
      // ---- partial output --------------------------------------------------------------------------------
      {"partial", "output_name_taken_by_a_folder", {{"out/stats.json/", ""}}, "solve -o {out} --quiet",
       {"{out}/stats.json", "not a regular file"}},
      {"partial", "render_camera_eye_1e20_in_scene",
       {{"s.json", scene(kLamp, R"(, "cameras": [ { "name": "a", "eye": [0,0,5], "look_at": [0,0,0] }, { "name": "b", "eye": [0,0,1e20], "look_at": [0,0,0] } ])")}},
       solve, {"{dir}/s.json", "cameras[1].eye[2]"}},
      // ---- misleading results ----------------------------------------------------------------------------
      {"misleading", "compare_black_reference", {{"a.exr", "<exr:grey>"}, {"b.exr", "<exr:black>"}},
       "compare {dir}/a.exr {dir}/b.exr -o {out}/d.png", {"{dir}/b.exr", "black"}},
      {"misleading", "compare_inf_pixel", {{"a.exr", "<exr:inf>"}, {"b.exr", "<exr:grey>"}},
       "compare {dir}/a.exr {dir}/b.exr -o {out}/d.png", {"{dir}/a.exr", "pixel (1, 0)", "finite"}},
      {"misleading", "compare_lights_of_a_missing_scene", {{"a.exr", "<exr:grey>"}},
       "compare {dir}/a.exr {dir}/a.exr --exclude-lights {dir}/none.json -o {out}/d.png", {"{dir}/none.json"}},
      {"misleading", "directory_as_scene", {{"d.json/", ""}}, "solve {dir}/d.json -o {out}", {"{dir}/d.json", "directory"}},
      {"misleading", "huge_key_not_echoed_in_full",
       {{"s.json", withLamp(R"({ "type": "sphere", "material": ")" + std::string(10 << 20, 'k') + R"(", "center": [0,0,0], "radius": 1 })")}},
       solve, {"{dir}/s.json", "objects[1].material", "(10485760 bytes)"}},
      {"misleading", "huge_coordinates_not_zero_area",
       {{"s.json", withLamp(R"({ "type": "quad", "material": "w", "vertices": [[1e20,0,0],[1e20,1,0],[1e20,1,1],[1e20,0,1]] })")}},
       "info {dir}/s.json", {"{dir}/s.json", "objects[1].vertices[0][0]"}},
  };
  // Every flag value of the issue's list (and a few more): refused, naming the flag. Each flag comes
  // first, so the expected name is the first "--" word.
  const std::vector<std::pair<const char*, std::string>> flags = {
      {"eps_0", "solve --eps 0 -o {out}"}, {"eps_negative", "solve --eps -1 -o {out}"}, {"eps_nan", "solve --eps nan -o {out}"},
      {"max_level_negative", "solve --max-level -1 -o {out}"}, {"max_level_100", "solve --max-level 100 -o {out}"},
      {"threads_0", "solve --threads 0 -o {out}"}, {"threads_negative", "solve --threads -1 -o {out}"},
      {"max_iterations_0", "solve --max-iterations 0 -o {out}"}, {"tolerance_negative", "solve --tolerance -1 -o {out}"},
      {"seed_negative", "solve --seed -1 -o {out}"}, {"seed_2_pow_32", "solve --seed 4294967296 -o {out}"},
      {"rays_per_link_0", "solve --rays-per-link 0 -o {out}"},
      {"max_imbalance_0", "solve --max-imbalance 0 -o {out}"}, {"max_imbalance_2", "solve --max-imbalance 2 -o {out}"},
      {"max_imbalance_nan", "solve --max-imbalance nan -o {out}"},
      {"spp_negative", "reference --spp -1 -o {out}"}, {"time_nan", "reference --time-s nan -o {out}"},
      {"reference_threads_0", "reference --threads 0 -o {out}"}, {"max_depth_0", "reference --max-depth 0 -o {out}"},
      {"lobe_eps_negative", "lobe --eps -1"}, {"lobe_min_level_negative", "lobe --min-level -1"},
      {"compare_mask_negative", "compare {dir}/a.exr {dir}/a.exr --mask -1"},
      // The glossy extension's options (issue 11), validated by the extension it belongs to.
      {"basis_unknown", "solve --basis foo --algorithm is -o {out}"},
      {"dir_eps_0", "solve --dir-eps 0 --algorithm is -o {out}"},
      {"dir_eps_negative", "solve --dir-eps -1 --algorithm is -o {out}"},
      {"dir_max_level_9", "solve --dir-max-level 9 --algorithm is -o {out}"},
      {"dir_min_above_max", "solve --dir-min-level 4 --algorithm is --dir-max-level 2 -o {out}"},
      {"sh_order_with_haar", "solve --sh-order 3 --algorithm is -o {out}"},
      {"reflection_refine_yes", "solve --reflection-refine yes --algorithm is -o {out}"},
      {"sender_extent_yes", "solve --sender-extent yes --algorithm is -o {out}"},
      {"tetra_level_with_sh", "solve --tetra-level 2 --algorithm is --basis sh -o {out}"},
      {"extension_option_without_extension", "solve --basis haar --algorithm diffuse -o {out}"},
      // --basis auto (issue 17): the spelling is exact, and every basis's options keep their ranges.
      {"basis_auto_capitalised", "solve --basis Auto --algorithm is -o {out}"},
      {"basis_auto_tetra_level_9", "solve --tetra-level 9 --basis auto --algorithm is -o {out}"},
      {"basis_auto_with_diffuse", "solve --basis auto --algorithm diffuse -o {out}"},
      // Shooting (issue 13).
      {"iteration_unknown", "solve --iteration foo -o {out}"},
      {"shoot_fraction_0", "solve --shoot-fraction 0 --iteration shoot -o {out}"},
      {"shoot_fraction_nan", "solve --shoot-fraction nan --iteration shoot -o {out}"},
      {"shoot_fraction_when_gathering", "solve --shoot-fraction 0.5 -o {out}"},
      {"iteration_shoot_with_rc", "solve --iteration shoot --algorithm rc -o {out}"},
      {"iteration_gather_on_vision", "solve --iteration gather --host vision -o {out}"},
      {"memory_mb_tiny", "solve --memory-mb 1 -o {out}"},
      {"memory_mb_nan", "solve --memory-mb nan -o {out}"},
      {"memory_mb_when_shooting", "solve --memory-mb 500 --iteration shoot -o {out}"},
      {"memory_mb_on_vision", "solve --memory-mb 500 --host vision -o {out}"},
  };
  for (const auto& [name, args] : flags) {
    std::size_t at = args.find("--");
    c.push_back({"default", name, {{"a.exr", "<exr:grey>"}}, args, {args.substr(at, args.find(' ', at) - at)}});
  }
  return c;
}

void PrintTo(const Case& c, std::ostream* os) { *os << c.cls << "/" << c.name; }

std::string replaced(std::string s, const fs::path& dir, const fs::path& out) {
  for (auto [key, value] : {std::pair<std::string, std::string>{"{dir}", dir.string()}, {"{out}", out.string()}})
    for (std::size_t at; (at = s.find(key)) != std::string::npos;) s.replace(at, key.size(), value);
  return s;
}

void writeExr(const fs::path& p, float value, bool inf) {
  const int w = 4, h = 2;
  std::vector<float> rgb(3 * w * h, value);
  if (inf) rgb[3] = std::numeric_limits<float>::infinity();  // pixel (1, 0)
  Imf::Header header(w, h);
  for (const char* n : {"R", "G", "B"}) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
  Imf::OutputFile file(p.c_str(), header);
  Imf::FrameBuffer fb;
  const char* names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c)
    fb.insert(names[c], Imf::Slice(Imf::FLOAT, (char*)(rgb.data() + c), 3 * sizeof(float), 3 * sizeof(float) * w));
  file.setFrameBuffer(fb);
  file.writePixels(h);
}

/// Every file under dir with its bytes.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    std::string key = fs::relative(e.path(), dir).string();
    if (e.is_regular_file()) {
      std::ifstream in(e.path(), std::ios::binary);
      m[key].assign(std::istreambuf_iterator<char>(in), {});
    } else {
      m[key + "/"] = "";
    }
  }
  return m;
}

class HostileInput : public ::testing::TestWithParam<Case> {};

TEST_P(HostileInput, ExitTwoNamingFileAndKeyNothingWritten) {
  const Case& c = GetParam();
  const fs::path dir = testutil::testDir(), out = dir / "out";
  fs::create_directories(out);
  for (const File& f : c.files) {
    fs::path p = dir / f.name;
    if (!f.name.empty() && f.name.back() == '/') {
      fs::create_directories(dir / f.name.substr(0, f.name.size() - 1));
    } else if (f.content == "<fifo>") {
      ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0);
    } else if (f.content.rfind("<link:", 0) == 0) {
      fs::create_symlink(f.content.substr(6, f.content.size() - 7), p);
    } else if (f.content.rfind("<exr:", 0) == 0) {
      writeExr(p, f.content == "<exr:black>" ? 0.0f : 0.5f, f.content == "<exr:inf>");
    } else {
      std::ofstream(p, std::ios::binary) << replaced(f.content, dir, out);
    }
  }
  // A previous run's outputs (unless a case put something else there): they must survive untouched.
  if (!fs::exists(out / "solution.ghrs")) std::ofstream(out / "solution.ghrs") << "previous solution";
  if (!fs::exists(out / "stats.json")) std::ofstream(out / "stats.json") << "{\"previous\": true}";
  const auto before = snapshot(out);
  std::string text;
  int status = testutil::runCli(replaced(c.args, dir, out), text);
  ASSERT_TRUE(WIFEXITED(status)) << text;
  EXPECT_EQ(WEXITSTATUS(status), 2) << text;
  for (const std::string& e : c.expect) EXPECT_NE(text.find(replaced(e, dir, out)), std::string::npos) << "expected \"" << replaced(e, dir, out) << "\" in: " << text.substr(0, 2000);
  EXPECT_LT(text.size(), 4000u) << "messages quote user input briefly";
  EXPECT_EQ(snapshot(out), before) << "the output folder must stay exactly as it was";
}

INSTANTIATE_TEST_SUITE_P(Issue12, HostileInput, ::testing::ValuesIn(cases()),
                         [](const auto& tp) { return std::string(tp.param.cls) + "_" + tp.param.name; });

/// A UTF-8 byte-order mark (Windows editors write one) is not part of the first entity.
TEST(HostileInputAccepted, ByteOrderMarkInMgfAndObj) {
  const fs::path dir = testutil::testDir();
  const std::string bom = "\xEF\xBB\xBF";
  std::ofstream(dir / "b.mgf") << bom + kMgfLamp;
  std::ofstream(dir / "b.obj") << bom + "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(dir / "s.json") << mesh("b.obj");
  std::string text;
  EXPECT_EQ(testutil::runCli("info " + (dir / "b.mgf").string(), text), 0) << text;
  EXPECT_EQ(testutil::runCli("info " + (dir / "s.json").string(), text), 0) << text;
  EXPECT_NE(text.find("patches after tessellation: 2"), std::string::npos) << text;
}

}  // namespace
