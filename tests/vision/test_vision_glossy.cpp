// The glossy extension on the VISION-like host (adapters/vision; issue 14 item 3), checked against
// conservation, the other host and itself: a closed glossy furnace keeps its energy and reflects
// what the BRIGHT-like host reflects; 1 and 2 threads give the same bytes; the three-lights image
// lies within a stated bar of the BRIGHT-like host's; a solution's extension section renders back to
// the same image; Radiance Clustering, which gathers only, is refused with exit 2; a shiny sphere's
// highlight sits where the mirror law puts it on both hosts; the display cells' section refuses damage.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <hr/camera.h>
#include <hr/output.h>
#include <hr/solution_view.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "../helpers.h"
#include "../sample_recorder.h"
#include "../test_dir.h"
#include "registry.h"
#include "vision/display_cells.h"
#include "vision_helpers.h"
#include "../saved_bytes.h"
#include "../whole_sample_lists.h"

namespace {

std::string sceneText(const char* name) {
  std::ifstream in(std::string(GHR_SOURCE_DIR) + "/scenes/" + name);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The power the extension sends on from every leaf, W per channel.
hr::Rgb reflected(const visiontest::Solved& s, const hr::Extension& ext) {
  hr::Rgb sum(0.0);
  for (const vision::Element* e : s.leaves()) sum += ext.reflectedPower(hr::NodeId{e->id});
  return sum;
}

TEST(VisionGlossy, ClosedFurnaceKeepsEnergyAndReflectsAsTheOtherHost) {
  // rho_d = 0, rho_s = 0.5: every reflection goes through the extension's hooks. Closed: nothing may
  // escape, and absorbed = emitted within 1 %. The power it reflects has no closed form (the Phong
  // lobe's albedo falls toward grazing), so it is checked against the BRIGHT-like host, within 2 %
  // (the two hosts' meshes and oracles differ), and must be at least a quarter of the emitted power
  // (without the hooks it would be 0; measured: half). At the scene's own eps 4e-4: 9.43 W against
  // 9.47 W (0.996). At eps 1e-3, where the test ran until wide senders were reflected as their disks,
  // the BRIGHT-like host's coarse walls, each seen as a disk nearly as wide as the box, reflect 2 %
  // more than at 4e-4 (9.63 W; the VISION-like host's 9.43 W does not move), 0.979 between the hosts.
  const std::string json = sceneText("glossy_furnace.json");
  hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(json, "").settings);
  auto ev = adapters::findExtension("is").make();
  auto v = visiontest::solveText(json, o, ev.get());
  ASSERT_TRUE(v.stats.converged);
  auto eb = adapters::findExtension("is").make();
  auto b = testutil::solveText(json, o, eb.get());
  hr::Rgb rb(0.0);
  for (std::uint32_t i = 0; i < b.h->elements().size(); ++i)
    if (b.h->elements()[i].leaf()) rb += eb->reflectedPower(hr::NodeId{i});
  const hr::Rgb rv = reflected(v, *ev);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(v.stats.absorbedW[c] / v.stats.emittedW[c], 1.0, 0.01) << "channel " << c;
    EXPECT_LT(v.stats.escapedW[c], 1e-3 * v.stats.emittedW[c]);
    EXPECT_GT(rv[c], 0.25 * v.stats.emittedW[c]);
    EXPECT_NEAR(rv[c] / rb[c], 1.0, 0.02) << "reflected power, vision " << rv[c] << " W, bright " << rb[c] << " W";
  }
  std::printf("glossy furnace: absorbed/emitted %.5f, reflected vision %.4f W, bright %.4f W (ratio %.4f)\n",
              v.stats.absorbedW.y / v.stats.emittedW.y, rv.y, rb.y, rv.y / rb.y);
}

TEST(VisionGlossy, EverySampleALeafReflectsPointsAtItsSenderFromThatLeaf) {
  // As on the other host: what this host carries down from an inner element or a cluster is re-aimed
  // from each child's centre, so at every leaf of the glossy furnace (every wall glossy) the leaf's
  // centre plus a sample's distance along its direction lands on its sender's centre within 0.1 mm:
  // a node's, or a part's (a leaf here shoots as the parts it would split into; the walls lie in
  // axis planes, so the parts' centres follow from the leaves' bounds).
  const std::string json = sceneText("glossy_furnace.json");
  hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(json, "").settings);
  o.eps = 2e-3;
  testutil::AimChecker ext;
  ext.partLevels = 4;
  visiontest::solveText(json, o, &ext);
  std::printf("%llu samples at leaves checked, %llu missed their sender, %llu of unknown distance\n",
              (unsigned long long)ext.checked.load(), (unsigned long long)ext.missed.load(),
              (unsigned long long)ext.unknown.load());
  EXPECT_GT(ext.checked.load(), 10000u);
  EXPECT_EQ(ext.missed.load(), 0u);
  EXPECT_EQ(ext.unknown.load(), 0u);
}

TEST(VisionGlossy, ASampleNamesItsFlatSendersNormal) {
  // As on the other host (Hooks.ASampleNamesItsFlatSendersNormal): a tilted lamp's light reaches the
  // glossy floor in samples that name the lamp's normal and the shape of one of its pieces, or none
  // (a cluster sender).
  hr::SolverOptions o;
  o.eps = 1e-3;
  o.iteration = hr::Iteration::Shoot;
  testutil::SampleRecorder rec;
  visiontest::solveText(testutil::kTiltedLampOverGlossyFloor, o, &rec);
  const testutil::LampSamples l = testutil::samplesNamingTheLamp(rec, false);
  std::printf("%zu samples, %zu name the lamp's normal, %zu another, %zu a shape not one of its pieces "
              "(finest: a side halved %d times)\n",
              rec.seen.size(), l.named, l.wrong, l.misshapen, l.finest);
  EXPECT_GT(l.named, 0u);
  EXPECT_EQ(l.wrong, 0u);
  EXPECT_EQ(l.misshapen, 0u);
  EXPECT_GT(l.finest, 0);  // pieces, not only the whole lamp
}

TEST(VisionGlossy, ReflectionInLayersGivesTheWholeSampleListsAnswer) {
  // Shooting passes on flat glossy walls (the glossy furnace) with the host offering an inner
  // element's samples once for its subtree (Extension::reflectShared; all of them, none re-aimed:
  // testutil::LayersTakingAll) and with every leaf given all
  // of its and its ancestors' samples: every leaf reflects the same power within 1e-4 (merging groups
  // samples per layer instead of per leaf), radiosity within 1e-4, and the layers took most samples.
  const std::string json = sceneText("glossy_furnace.json");
  hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(json, "").settings);
  o.eps = 2e-3;
  auto layered = std::make_unique<testutil::LayersTakingAll>();
  testutil::WholeSampleLists whole;
  auto a = visiontest::solveText(json, o, layered.get());
  auto b = visiontest::solveText(json, o, &whole);
  const auto la = a.leaves(), lb = b.leaves();
  ASSERT_EQ(la.size(), lb.size());
  testutil::expectLayersTookMostSamples(*layered, whole);
  double worstPower = 0.0, worstB = 0.0;
  for (std::size_t i = 0; i < la.size(); ++i) {
    ASSERT_EQ(la[i]->id, lb[i]->id);
    worstB = std::max(worstB, hr::maxComponent(glm::abs(la[i]->B - lb[i]->B)) / std::max(1e-9, hr::maxComponent(lb[i]->B)));
    const hr::Rgb pa = layered->reflectedPower(hr::NodeId{la[i]->id}), pb = whole.reflectedPower(hr::NodeId{lb[i]->id});
    if (!(hr::maxComponent(pb) > 0.0)) continue;
    worstPower = std::max(worstPower, hr::maxComponent(glm::abs(pa - pb)) / hr::maxComponent(pb));
  }
  std::printf("worst leaf: reflected power %.2e, radiosity %.2e (relative)\n", worstPower, worstB);
  EXPECT_LT(worstPower, 1e-4);
  EXPECT_LT(worstB, 1e-4);
}

TEST(VisionGlossy, OneAndTwoThreadsBitIdentical) {
  const std::string json = sceneText("glossy_furnace.json");
  hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(json, "").settings);
  o.eps = 2e-3;
  std::string bytes[2];
  hr::SolveStats st[2];
  for (int t = 1; t <= 2; ++t) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t));
    auto ext = adapters::findExtension("is").make();
    auto s = visiontest::solveText(json, o, ext.get());
    bytes[t - 1] = testutil::savedBytes(*ext);  // reads the leaves through the solver's view: s is still alive
    st[t - 1] = s.stats;
  }
  EXPECT_GT(bytes[0].size(), 1000u);
  EXPECT_TRUE(bytes[0] == bytes[1]) << "the extension's distributions bit for bit";
  EXPECT_EQ(st[0].rays, st[1].rays);
  EXPECT_EQ(std::memcmp(&st[0].absorbedW, &st[1].absorbedW, sizeof(hr::Rgb)), 0);
  EXPECT_GE(st[1].pushPull.threads, 2) << "the two-thread run did use two threads";
}

double relRmse(const std::string& a, const std::string& b, const std::string& exclude) {
  std::string out;
  EXPECT_EQ(testutil::runCli("compare " + a + " " + b + " --json" + exclude, out), 0) << out;
  return nlohmann::json::parse(out.substr(out.find('{')))["rel_rmse"].get<double>();
}

TEST(VisionGlossyCli, ThreeLightsAgainstTheOtherHostAndRenderedBack) {
  namespace fs = std::filesystem;
  const fs::path dir = testutil::testDir();
  const std::string scene = std::string(GHR_SOURCE_DIR) + "/scenes/three_lights.json", lights = " --exclude 3,4,5";
  std::string out;
  // The diffuse run only shows that the spots matter (at eps 1e-4 it lies 0.238 from the glossy
  // BRIGHT-like image at the scene's 4e-5; the bar below is 0.2): a coarser eps spares its time.
  const std::pair<const char*, const char*> runs[] = {
      {"visionis", "vision --algorithm is"},
      {"brightis", "bright --algorithm is"},
      {"visiondiffuse", "vision --algorithm diffuse --eps 1e-4"}};
  for (const auto& [name, run] : runs)
    ASSERT_EQ(testutil::runCli("solve " + scene + " --host " + run + " --quiet -o " + (dir / name).string(), out), 0) << out;
  const std::string vis = (dir / "visionis" / "overview.exr").string(), bri = (dir / "brightis" / "overview.exr").string();
  // Issue 14's bar between the hosts, 0.05, at the scene's own settings. At eps 1e-4 the two lay
  // 0.078 apart, most of it the BRIGHT-like host's floor under the reflector's coloured shadows (its
  // elements stopped at a sixteenth of the shadow's width); at the scene's eps 4e-5 since, 0.038, with
  // the BRIGHT-like image 0.044-0.053 from a 16,384-spp reference (0.088-0.093 at 1e-4; docs/hosts.md).
  // Without the extension's spots the VISION-like image is far from the BRIGHT-like glossy one.
  const double e = relRmse(vis, bri, lights);
  EXPECT_LT(e, 0.05) << "vision vs bright, both glossy";
  EXPECT_GT(relRmse((dir / "visiondiffuse" / "overview.exr").string(), bri, lights), 0.2) << "the spots matter";
  std::printf("three lights, rel RMSE vision vs bright (lights masked): %.4f\n", e);
  // The solution file's extension section (the adapter's display cells) renders the same image.
  ASSERT_EQ(testutil::runCli("render " + (dir / "visionis" / "solution.ghrs").string() + " -o " + (dir / "again.exr").string() +
                                 " --quiet", out), 0) << out;
  EXPECT_EQ(relRmse((dir / "again.exr").string(), vis, ""), 0.0);
}

TEST(VisionGlossyCli, GlossyCornellAgainstTheOtherHost) {
  // Issue 14's bar between the hosts, 0.05, on the glossy Cornell box at its own settings (lights
  // left out). Most of what is left is the tall glossy block (0.24-0.25 between the hosts on its
  // pixels; each 0.20-0.26 from a 4,096-spp reference). It read 0.067 before samples were re-aimed at
  // every leaf (main at 1fbb598: fails), 0.0499 / 0.0505 / 0.0510 for seeds 1-3 after (what
  // --sender-extent off gives: seed 1 passes by a hair, seeds 2 and 3 fail), and 0.0457 / 0.0466 /
  // 0.0465 since a wide sender is reflected as its disk (docs/glossy.md, "Senders as areas").
  namespace fs = std::filesystem;
  const fs::path dir = testutil::testDir();
  const std::string scene = std::string(GHR_SOURCE_DIR) + "/scenes/glossy_cornell.json";
  std::string out;
  for (const char* host : {"vision", "bright"})
    ASSERT_EQ(testutil::runCli("solve " + scene + " --host " + host + " --algorithm is --seed 1 --quiet -o " +
                                   (dir / host).string(), out),
              0)
        << out;
  const double e = relRmse((dir / "vision" / "front.exr").string(), (dir / "bright" / "front.exr").string(), " --exclude 5");
  std::printf("glossy Cornell, rel RMSE vision vs bright (light masked): %.4f\n", e);
  EXPECT_LT(e, 0.05);
}

TEST(VisionGlossyCli, RadianceClusteringIsRefusedNamingTheFlags) {
  std::string out;
  int rc = testutil::runCli("solve " + std::string(GHR_SOURCE_DIR) + "/scenes/glossy_cornell.json --host vision --algorithm rc --quiet -o " +
                                (testutil::testDir() / "out").string(), out);
  EXPECT_EQ(WEXITSTATUS(rc), 2) << out;
  EXPECT_NE(out.find("--algorithm rc gathers only, and --host vision shoots only"), std::string::npos) << out;
}

}  // namespace

namespace {

/// At the brightest pixel of a shiny sphere lit by one small lamp: the angle (degrees) between the
/// lamp and the mirror image of the eye about the sphere's exact normal there, 0 where the mirror law
/// puts the highlight. Pixels whose centre ray misses the sphere or grazes its rim are left out.
double highlightMirrorErrorDeg(const hr::Image& img, const hr::Camera& cam, const hr::Vec3& c, double r, const hr::Vec3& lamp) {
  const hr::CameraRays rays(cam);
  double best = -1.0, err = 180.0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const hr::Vec3 d = rays.dir(x + 0.5, y + 0.5), oc = cam.eye - c;
      const double b = glm::dot(oc, d), disc = b * b - (glm::dot(oc, oc) - r * r);
      if (disc <= 0.0) continue;
      const hr::Vec3 p = cam.eye + (-b - std::sqrt(disc)) * d, n = (p - c) / r, toEye = -d;
      if (glm::dot(n, toEye) < 0.2) continue;
      const std::size_t i = 3 * (std::size_t(y) * img.width + x);
      const double lum = 0.2126 * img.rgb[i] + 0.7152 * img.rgb[i + 1] + 0.0722 * img.rgb[i + 2];
      if (lum <= best) continue;
      best = lum;
      const hr::Vec3 m = 2.0 * glm::dot(n, toEye) * n - toEye;
      err = std::acos(std::clamp(glm::dot(m, glm::normalize(lamp - p)), -1.0, 1.0)) * 180.0 / hr::kPi;
    }
  return err;
}

TEST(GlossyDisplayCli, ASpheresHighlightSitsWhereTheMirrorLawPutsItOnBothHosts) {
  // A shiny sphere (lobe sqrt(2/800) = 2.9 degrees wide) under a lamp 1.8 degrees across, seen
  // closely (a pixel is 0.4 degrees of the sphere's normal, 0.8 of its mirror image): its brightest
  // pixel must be where the eye's mirror image about the sphere's normal meets
  // the lamp. A leaf's glossy light is one distribution reflected about one normal, so a display that
  // evaluates it as if the whole leaf faced that way puts the highlight where a leaf (or a flat facet
  // of the tessellated sphere) happens to face best, by up to half a leaf's turn times two; evaluated
  // at each pixel's own normal it sits where the surface puts it.
  namespace fs = std::filesystem;
  const fs::path dir = testutil::testDir();
  const std::string scene = R"({ "name": "highlight",
    "materials": { "shiny": { "diffuse": [0.05, 0.05, 0.05], "specular": [0.5, 0.5, 0.5], "exponent": 800 },
                   "lamp": { "emission": [2000, 2000, 2000] } },
    "objects": [ { "type": "sphere", "material": "shiny", "center": [0, 0, 0], "radius": 0.5 },
                 { "type": "quad", "material": "lamp", "vertices": [[-0.05,3,0.95],[0.05,3,0.95],[0.05,3,1.05],[-0.05,3,1.05]] } ],
    "cameras": [ { "name": "c", "eye": [0, 0.5, 4], "look_at": [0, 0.3, 0.4], "up": [0, 1, 0], "fov_y_deg": 8, "width": 160, "height": 160 } ],
    "settings": { "tessellation": 16 } })";
  const fs::path file = dir / "highlight.json";
  std::ofstream(file) << scene;
  const hr::Camera cam = hr::parseScene(scene, "").cameras.at(0);
  // Bar 1 degree, about a pixel's 0.8, on both hosts (docs/glossy.md, "Highlights at display"): the
  // BRIGHT-like host's 16 facets are shaded at the sphere's own point where the eye ray meets the
  // sphere, measured 0.54 (2.47 at the sphere's normal where the ray meets the facet, inside the
  // sphere; 3.47 with normals estimated from the facets, 67.6 without any); the VISION-like host's
  // exact sphere 0.54 with the lamp reflected exactly at each pixel, 0.70 with the stored
  // distribution alone (--exact-highlights off; 2.71 without the normal).
  const std::pair<const char*, double> hosts[] = {{"bright", 1.0}, {"vision", 1.0}};
  for (const auto& [host, bar] : hosts) {
    std::string out;
    ASSERT_EQ(testutil::runCli("solve " + file.string() + " --host " + host + " --algorithm is --quiet -o " + (dir / host).string(), out), 0) << out;
    const double e = highlightMirrorErrorDeg(hr::readExr((dir / host / "c.exr").string()), cam, hr::Vec3(0.0), 0.5, hr::Vec3(0, 3, 1));
    std::printf("%s: the brightest pixel lies %.2f degrees off the mirror law\n", host, e);
    EXPECT_LT(e, bar) << host;
  }
}

}  // namespace

namespace {

TEST(VisionGlossy, ACellCarriesItsShareOfItsLeafsLight) {
  // After the solve, the solution's elements are display cells, and solution.vtp and `inspect` ask
  // the extension for each cell's reflected power and intensity. A cell's id read as a leaf's gave
  // another leaf's light (the shiny sphere's cells at its highlight read 0 W). Now each cell carries
  // its area's share of its leaf's, so a leaf's cells sum to the leaf, as measured before the cells
  // were shown: power and intensity along the leaf's normal, to rounding.
  const std::string json = sceneText("glossy_sphere.json");
  hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(json, "").settings);
  o.eps = 2e-3, o.maxLevel = 2;
  auto ext = adapters::vision::adapt(adapters::findExtension("is").make());
  auto v = visiontest::solveText(json, o, ext.get());
  std::map<std::uint32_t, std::pair<hr::Rgb, hr::Rgb>> leaf;  // power, intensity along its normal
  for (const vision::Element* e : v.leaves()) {
    const hr::NodeId id{e->id};
    const hr::Vec3 n = v.solver->view().info(id).normal;
    leaf[e->id] = {ext->reflectedPower(id), ext->intensity(id, n)};
  }
  std::vector<std::uint32_t> cellLeaf;
  const hr::Solution sol = vision::makeSolution(v.scene, *v.h, vision::Display::Smooth, &cellLeaf);
  adapters::vision::showCells(*ext, v.solver->view(), sol, cellLeaf);
  std::map<std::uint32_t, std::pair<hr::Rgb, hr::Rgb>> sum;
  for (std::uint32_t c = 0; c < cellLeaf.size(); ++c) {
    const hr::Vec3 n = v.solver->view().info(hr::NodeId{cellLeaf[c]}).normal;
    sum[cellLeaf[c]].first += ext->reflectedPower(hr::NodeId{c});
    sum[cellLeaf[c]].second += ext->intensity(hr::NodeId{c}, n);
  }
  std::size_t lit = 0;
  for (const auto& [id, want] : leaf) {
    if (!(want.first.y > 0.0)) continue;
    ++lit;
    EXPECT_NEAR(sum[id].first.y / want.first.y, 1.0, 1e-9) << "leaf " << id << "'s cells' power";
    if (want.second.y > 0.0) {
      EXPECT_NEAR(sum[id].second.y / want.second.y, 1.0, 1e-9) << "leaf " << id << "'s cells' intensity";
    }
  }
  EXPECT_GT(lit, 10u);
  std::printf("%zu lit glossy leaves in %zu cells\n", lit, cellLeaf.size());
}

TEST(VisionGlossyCli, TheCellsSectionRefusesDamageAndTheOlderLayout) {
  // The adapter's part of a VISION solution's extension section (magic, H, each cell's leaf, the
  // shown leaves) is read before the extension's: truncated anywhere, a cell naming a leaf beyond H,
  // or the layout of before 2026-12-03 (a copy per cell), it is refused with an InputError naming
  // the section, never read past its end; intact, every cell's radiance is finite. Two levels of
  // elements hold curved leaves and their cells as well as the scene's four do (3 s, not 25 s, to solve).
  namespace fs = std::filesystem;
  const fs::path dir = testutil::testDir();
  std::string out;
  ASSERT_EQ(testutil::runCli("solve " + std::string(GHR_SOURCE_DIR) +
                                 "/scenes/glossy_sphere.json --host vision --algorithm is --eps 2e-3 --max-level 2 --quiet -o " +
                                 (dir / "s").string(),
                             out),
            0)
      << out;
  const hr::Solution sol = hr::loadSolution((dir / "s" / "solution.ghrs").string());
  const hr::SolutionView view(sol);
  const std::string& bytes = sol.extension.bytes;
  auto load = [&](const std::string& b) {
    auto ext = adapters::vision::adapt(adapters::findExtension("is").make());
    ext->load(b, view);
    return ext;
  };
  auto intact = load(bytes);
  std::size_t lit = 0;
  for (std::uint32_t i = 0; i < sol.elements.size(); ++i) {
    const hr::Vec3 n = sol.patches[sol.elements[i].patch].normal;
    const hr::Rgb L = intact->radiance(hr::NodeId{i}, n), Ln = intact->radiance(hr::NodeId{i}, n, n);
    ASSERT_TRUE(hr::allFinite(L) && hr::allFinite(Ln)) << i;
    EXPECT_EQ(L, Ln) << "a cell asked at its own normal, either way";
    lit += L.x > 0.0 ? 1 : 0;
  }
  EXPECT_GT(lit, 0u) << "some cells show glossy light";
  const std::uint32_t H = std::uint32_t(static_cast<unsigned char>(bytes[4])) | std::uint32_t(static_cast<unsigned char>(bytes[5])) << 8 |
                          std::uint32_t(static_cast<unsigned char>(bytes[6])) << 16 | std::uint32_t(static_cast<unsigned char>(bytes[7])) << 24;
  const std::size_t header = 12 + 4 * sol.elements.size();
  for (std::size_t cut : {std::size_t(0), std::size_t(3), std::size_t(8), std::size_t(11), header - 2, header + 2, header + 40})
    EXPECT_THROW(load(bytes.substr(0, cut)), hr::InputError) << "cut at " << cut;
  std::string old = bytes;
  old[0] = 'V', old[1] = 'I', old[2] = 'S', old[3] = 'C';
  try {
    load(old);
    ADD_FAILURE() << "the older layout was read";
  } catch (const hr::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("solve the scene again"), std::string::npos) << e.what();
  }
  std::string far = bytes;
  for (int k = 0; k < 4; ++k) far[12 + std::size_t(k)] = char((H >> (8 * k)) & 0xFF);  // cell 0 names leaf H
  EXPECT_THROW(load(far), hr::InputError);
}

}  // namespace

namespace {

TEST(VisionGlossyCli, AMirrorNearACardIsRefinedByTheReflectorOnThisHostToo) {
  // A mirror (n = 1000) 0.05 m below a lit card: a receiver that sees the card from directions
  // further apart than its lobe reflects it as blobs unless the oracle refines for the reflection
  // (hr::Reflector, --reflection-refine). This host's adapter did not pass reflector() on, so the
  // flag did nothing here: the mirror's pixels lay 1.25 from a path-traced reference either way.
  // Measured then: 0.34 with the default (on), 1.25 with --reflection-refine off (the reference's own
  // noise at 1,024 spp: 0.12-0.16). Since samples are re-aimed at every leaf and a wide sender is
  // reflected as its disk (docs/glossy.md), which do much of what the term did: 0.335 on, 0.546 off.
  namespace fs = std::filesystem;
  const fs::path dir = testutil::testDir();
  const std::string scene = R"({ "name": "mirror_card", "materials": { "l": { "emission": [12,12,12] }, "w": { "diffuse": [0.8,0.8,0.8] },
      "mirror": { "diffuse": [0,0,0], "specular": [0.9,0.9,0.9], "exponent": 1000 } },
    "objects": [
      { "type": "quad", "material": "l", "vertices": [[-0.3,1.5,-1.6],[0.3,1.5,-1.6],[0.3,1.5,-1.0],[-0.3,1.5,-1.0]] },
      { "type": "quad", "material": "mirror", "vertices": [[-0.6,0,-0.6],[-0.6,0,0.6],[0.6,0,0.6],[0.6,0,-0.6]] },
      { "type": "quad", "material": "w", "vertices": [[0.2,0.05,0],[-0.2,0.05,0],[-0.2,0.35,0],[0.2,0.35,0]] } ],
    "cameras": [ { "name": "mirror", "eye": [0, 0.9, -2.2], "look_at": [0, 0.05, 0], "up": [0,1,0], "fov_y_deg": 24, "width": 160, "height": 120 } ],
    "settings": { "eps": 2e-4 } })";
  const fs::path file = dir / "mirror_card.json";
  std::ofstream(file) << scene;
  std::string out;
  ASSERT_EQ(testutil::runCli("reference " + file.string() + " --spp 1024 --quiet -o " + (dir / "ref").string(), out), 0) << out;
  double err[2];
  for (int k = 0; k < 2; ++k) {
    const std::string o = (dir / (k ? "off" : "on")).string();
    ASSERT_EQ(testutil::runCli("solve " + file.string() + " --host vision --algorithm is --reflection-refine " + (k ? "off" : "on") +
                                   " --quiet -o " + o, out), 0) << out;
    err[k] = relRmse(o + "/mirror.exr", (dir / "ref" / "mirror.exr").string(), " --mask 1");
  }
  std::printf("mirror near a card on the VISION-like host, rel RMSE: on %.3f, off %.3f\n", err[0], err[1]);
  EXPECT_LT(err[0], 0.5) << "refined for the reflection";
  EXPECT_GT(err[1], 1.4 * err[0]) << "without it (the flag must matter)";
}

}  // namespace
