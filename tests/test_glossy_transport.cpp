// Glossy transport end to end, host and extension together (--algorithm is): the spots a glossy
// reflector throws on a wall against an independent integration of the optics, energy with glossy
// surfaces, a diffuse scene's bits unchanged by the extension, saved solutions that render from any
// camera like a fresh solve, hard cases, and thread independence.
#include <glossy/illumination_samples.h>
#include <gtest/gtest.h>
#include <hr/auto_camera.h>
#include <hr/camera.h>
#include <hr/output.h>
#include <hr/rng.h>
#include <hr/solution_view.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include <filesystem>

#include "helpers.h"
#include "registry.h"
#include "test_dir.h"
#include "saved_bytes.h"
#include "whole_sample_lists.h"

namespace fs = std::filesystem;

namespace {

std::string readFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::unique_ptr<hr::Extension> makeIs(const std::vector<hr::OptionValue>& options = {}) {
  auto ext = adapters::findExtension("is").make();
  ext->configure(options);
  return ext;
}

/// The light an object receives: per-channel power (W) and its centroid (m), from a glossy solve.
struct Spot {
  hr::Rgb power{0.0};
  hr::Vec3 centroid[3];
};

Spot receivedBy(const testutil::Solved& run, std::uint32_t object) {
  Spot s;
  hr::Vec3 moment[3] = {hr::Vec3(0.0), hr::Vec3(0.0), hr::Vec3(0.0)};
  for (std::size_t i = 0; i < run.h->elements().size(); ++i) {
    const auto& e = run.h->element(static_cast<std::uint32_t>(i));
    if (!e.leaf() || run.h->patches()[e.patch].object != object) continue;
    hr::Rgb p = e.area * run.solver->irradiance()[i];
    s.power += p;
    for (int c = 0; c < 3; ++c) moment[c] += p[c] * e.center;
  }
  for (int c = 0; c < 3; ++c) s.centroid[c] = moment[c] / s.power[c];
  return s;
}

/// The same, integrated from the optics alone: every light sends L_e from its disk to the
/// reflector (a grid of points over both), the reflector's specular lobe f_s = rho_s (n+2)/(2 pi)
/// cos^n(alpha) sends it on (directions drawn from the lobe, weight rho_s (n+2)/(n+1) cos theta_o),
/// and what reaches the wall plane is summed. One bounce, no solver involved.
Spot spotFromOptics(const hr::Scene& sc, std::uint32_t reflector, double wallZ) {
  const hr::Object& r = sc.objects[reflector];
  const hr::Material& m = sc.materials[sc.materialIndex.at(r.material)];
  const hr::Vec3 a = r.quad[0], b = r.quad[1], d = r.quad[3];
  const hr::Vec3 ea = b - a, eb = d - a, nr = glm::normalize(glm::cross(ea, eb));
  const double areaR = glm::length(glm::cross(ea, eb));
  Spot s;
  hr::Vec3 moment[3] = {hr::Vec3(0.0), hr::Vec3(0.0), hr::Vec3(0.0)};
  hr::Rng rng(7, 1);
  const int NR = 24, NL = 4, NO = 64;
  // The lights as the scene tessellates them (a 16-sided disk holds 2.6 % less area than a circle).
  hr::Scene copy = sc;
  hr::TessellationReport rep;
  const std::vector<hr::Patch> patches = hr::buildPatches(copy, rep);
  for (const hr::Patch& light : patches) {
    const hr::Material& lm = sc.materials[light.material];
    if (!lm.emitter()) continue;
    const hr::Vec3 nl = light.normal;
    const double areaL = light.area;
    for (int i = 0; i < NR * NR; ++i) {
      hr::Vec3 y = a + ea * ((i % NR + rng.uniform()) / NR) + eb * ((i / NR + rng.uniform()) / NR);
      for (int j = 0; j < NL; ++j) {
        hr::Vec3 z = light.poly.sample((j + rng.uniform()) / NL, rng.uniform());
        hr::Vec3 wi = z - y;
        double dist2 = glm::dot(wi, wi);
        wi /= std::sqrt(dist2);
        double ci = glm::dot(nr, wi), cz = -glm::dot(nl, wi);
        if (ci <= 0.0 || cz <= 0.0) continue;
        // Irradiance at y from this bit of the light, times y's share of the reflector's area, W/m^2 * m^2.
        hr::Rgb dPhi = lm.emission * (ci * cz / dist2) * (areaL / NL) * (areaR / (NR * NR));
        const hr::Vec3 mir = 2.0 * glm::dot(nr, wi) * nr - wi;
        hr::Vec3 mu, mv;
        hr::Vec3 t = std::abs(mir.x) > 0.9 ? hr::Vec3(0, 1, 0) : hr::Vec3(1, 0, 0);
        mu = glm::normalize(glm::cross(t, mir)), mv = glm::cross(mir, mu);
        for (int k = 0; k < NO; ++k) {
          double cosA = std::pow(rng.uniform(), 1.0 / (m.exponent + 1.0)), sinA = std::sqrt(1.0 - cosA * cosA);
          double ph = 2.0 * hr::kPi * rng.uniform();
          hr::Vec3 wo = cosA * mir + sinA * (std::cos(ph) * mu + std::sin(ph) * mv);
          double co = glm::dot(nr, wo);
          if (co <= 0.0) continue;
          if (wo.z >= 0.0) continue;
          double tt = (wallZ - y.z) / wo.z;
          hr::Vec3 h = y + tt * wo;
          if (std::abs(h.x) > 3.0 || h.y < 0.0 || h.y > 3.0) continue;
          hr::Rgb p = dPhi * m.specular * ((m.exponent + 2.0) / (m.exponent + 1.0) * co / NO);
          s.power += p;
          for (int c = 0; c < 3; ++c) moment[c] += p[c] * h;
        }
      }
    }
  }
  for (int c = 0; c < 3; ++c) s.centroid[c] = moment[c] / s.power[c];
  return s;
}

TEST(GlossyTransport, ThreeLightsSpotsLandWhereTheOpticsPutThem) {
  // The three-lights scene with a black floor and a reflector without a diffuse part: all the wall
  // receives is then what the reflector's lobe throws on it (the lights face away from the wall), one
  // bounce, which the optics integrate without the solver.
  std::string json = readFile(std::string(GHR_SOURCE_DIR) + "/scenes/three_lights.json");
  auto blacken = [&](const std::string& mat, const std::string& from) {
    auto at = json.find("\"" + mat + "\"");
    ASSERT_NE(at, std::string::npos);
    at = json.find(from, at);
    ASSERT_NE(at, std::string::npos);
    json.replace(at, from.size(), "\"diffuse\": [0, 0, 0]");
  };
  blacken("floor", "\"diffuse\": [\n    0.4,\n    0.4,\n    0.4\n   ]");
  blacken("reflector", "\"diffuse\": [\n    0.05,\n    0.05,\n    0.05\n   ]");
  hr::Scene sc = hr::parseScene(json, "three_lights.json");
  hr::SolverOptions o = hr::SolverOptions::from(sc.settings);
  auto ext = makeIs();
  auto run = testutil::solveText(json, o, ext.get());
  Spot got = receivedBy(run, 1), want = spotFromOptics(sc, 2, -3.0);
  std::printf("spot power (W, RGB) %.4g %.4g %.4g, optics %.4g %.4g %.4g; centroid offsets (cm) %.2f %.2f %.2f\n",
              got.power.x, got.power.y, got.power.z, want.power.x, want.power.y, want.power.z,
              100 * glm::length(got.centroid[0] - want.centroid[0]), 100 * glm::length(got.centroid[1] - want.centroid[1]),
              100 * glm::length(got.centroid[2] - want.centroid[2]));
  for (int c = 0; c < 3; ++c) {
    SCOPED_TRACE("channel " + std::to_string(c));
    EXPECT_NEAR(got.power[c] / want.power[c], 1.0, 0.05) << "spot power " << got.power[c] << " W vs " << want.power[c];
    EXPECT_LT(glm::length(got.centroid[c] - want.centroid[c]), 0.02)
        << "centroid (" << got.centroid[c].x << ", " << got.centroid[c].y << ") vs (" << want.centroid[c].x << ", "
        << want.centroid[c].y << ")";
  }
}

/// Emitted = absorbed + escaped within a tolerance, per channel, and the radiosity finite.
void expectBalanced(const testutil::Solved& s, double tol, const std::string& what) {
  for (int c = 0; c < 3; ++c) {
    if (s.stats.emittedW[c] <= 0.0) continue;
    double imbalance = (s.stats.emittedW[c] - s.stats.absorbedW[c] - s.stats.escapedW[c]) / s.stats.emittedW[c];
    EXPECT_LT(std::abs(imbalance), tol) << what << ", channel " << c;
  }
  for (const hr::Rgb& b : s.solver->radiosity()) ASSERT_TRUE(hr::allFinite(b)) << what;
}

TEST(GlossyTransport, ClosedGlossyFurnaceKeepsItsEnergy) {
  // Every face emits and reflects through the lobe only (rho_d 0, rho_s 0.5, n 20): nothing escapes,
  // all is absorbed where the lobe's albedo falls short of 1. At the scene's eps 4e-4 and at a coarse
  // 2e-3, whose large elements next to each other are what the near-field rule is for: its flux and
  // form factor taken at one point of the sender lost 0.62 % and 1.9 % (SolverState::extensionNearField);
  // from four points, 0.17 % and -0.10 %.
  std::string json = readFile(std::string(GHR_SOURCE_DIR) + "/scenes/glossy_furnace.json");
  for (double eps : {0.0, 2e-3}) {
    hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(json, "").settings);
    if (eps > 0.0) o.eps = eps;
    auto ext = makeIs();
    auto s = testutil::solveText(json, o, ext.get());
    ASSERT_TRUE(s.stats.converged);
    const double imbalance = (s.stats.emittedW[0] - s.stats.absorbedW[0] - s.stats.escapedW[0]) / s.stats.emittedW[0];
    std::printf("glossy furnace at eps %g: imbalance %.3f %% of the emitted power\n", o.eps, 100.0 * imbalance);
    expectBalanced(s, 0.005, "glossy furnace at eps " + std::to_string(o.eps));
    for (int c = 0; c < 3; ++c) EXPECT_LT(s.stats.escapedW[c], 1e-3 * s.stats.emittedW[c]);
  }
}

// The same furnace's image against the independent path tracer (issue 11: mean within 2 %). Every
// face emits and reflects only through its lobe, so the image is all glossy interreflection; the
// tracer's 64 spp over 160 x 160 pixels put the mean's standard error near 1e-3. Measured: 1.0028
// (also 1.0029 against 256 spp).
TEST(GlossyTransport, ClosedGlossyFurnaceImageMeanMatchesThePathTracer) {
  const fs::path dir = testutil::testDir();
  const std::string scene = std::string(GHR_SOURCE_DIR) + "/scenes/glossy_furnace.json";
  std::string out;
  ASSERT_EQ(testutil::runCli("solve " + scene + " --algorithm is --quiet -o " + (dir / "sol").string(), out), 0) << out;
  ASSERT_EQ(testutil::runCli("reference " + scene + " --spp 64 --seed 7 --quiet -o " + (dir / "ref").string(), out), 0) << out;
  auto meanLuminance = [](const hr::Image& im) {
    double sum = 0.0;
    for (std::size_t p = 0; p < im.rgb.size() / 3; ++p) sum += hr::luminance(hr::Rgb(im.rgb[3 * p], im.rgb[3 * p + 1], im.rgb[3 * p + 2]));
    return sum / double(im.rgb.size() / 3);
  };
  const double ratio = meanLuminance(hr::readExr((dir / "sol" / "inside.exr").string())) /
                       meanLuminance(hr::readExr((dir / "ref" / "inside.exr").string()));
  std::printf("glossy furnace: image mean / path tracer's = %.4f\n", ratio);
  EXPECT_NEAR(ratio, 1.0, 0.02);
}

/// Hard cases (issue 11): each finite everywhere with its energy within 1 %.
TEST(GlossyTransport, HardCasesStayFiniteAndBalanced) {
  const std::string lamp = R"({ "type": "quad", "material": "l", "vertices": [[-0.3,1.5,-0.3],[0.3,1.5,-0.3],[0.3,1.5,0.3],[-0.3,1.5,0.3]] })";
  const std::string mats = R"("l": { "emission": [5,5,5] }, "w": { "diffuse": [0.6,0.6,0.6] },
      "mirror": { "diffuse": [0.05,0.05,0.05], "specular": [0.9,0.9,0.9], "exponent": 10000 },
      "g": { "diffuse": [0.3,0.3,0.3], "specular": [0.6,0.6,0.6], "exponent": 200 })";
  auto scene = [&](const std::string& objects) {
    return R"({ "materials": { )" + mats + R"( }, "objects": [ )" + objects + " ] }";
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"near-mirror floor (n = 10^4) under a lamp",
       scene(R"({ "type": "quad", "material": "l", "vertices": [[-0.3,1.5,0.3],[0.3,1.5,0.3],[0.3,1.5,-0.3],[-0.3,1.5,-0.3]] },
              { "type": "quad", "material": "mirror", "vertices": [[-2,0,-2],[-2,0,2],[2,0,2],[2,0,-2]] },
              { "type": "quad", "material": "w", "vertices": [[-2,0,-2],[2,0,-2],[2,2,-2],[-2,2,-2]] })")},
      {"lamp at grazing incidence on a glossy floor",
       scene(R"({ "type": "quad", "material": "l", "vertices": [[-3,0.02,-0.3],[-3,0.32,-0.3],[-3,0.32,0.3],[-3,0.02,0.3]] },
              { "type": "quad", "material": "g", "vertices": [[-2,0,-2],[-2,0,2],[2,0,2],[2,0,-2]] },
              { "type": "quad", "material": "w", "vertices": [[2,0,-2],[2,0,2],[2,2,2],[2,2,-2]] })")},
      {"glossy and diffuse faces touching along an edge",
       scene(R"({ "type": "quad", "material": "l", "vertices": [[0.2,1.5,0.2],[0.8,1.5,0.2],[0.8,1.5,0.8],[0.2,1.5,0.8]] },
              { "type": "quad", "material": "g", "vertices": [[0,0,0],[0,0,1],[1,0,1],[1,0,0]] },
              { "type": "quad", "material": "w", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]] })")},
      {"glossy surface seen exactly edge-on",
       scene(lamp + R"(, { "type": "quad", "material": "g", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]] } ], "cameras": [
              { "name": "edge", "eye": [0,0,4], "look_at": [0,0,0], "up": [0,1,0], "fov_y_deg": 40, "width": 64, "height": 48 })")},
  };
  for (const auto& [what, json] : cases) {
    SCOPED_TRACE(what);
    hr::SolverOptions o;
    o.eps = 2e-4;
    auto ext = makeIs();
    auto s = testutil::solveText(json, o, ext.get());
    expectBalanced(s, 0.01, what);
    // Its images from the saved solution are finite too, the edge-on view included.
    hr::Solution sol = hr::makeSolution(s.scene, *s.h, s.solver->radiosity());
    if (sol.cameras.empty()) sol.cameras.push_back(hr::autoCamera(s.scene, s.h->patches(), *s.vis));
    for (const hr::Camera& cam : sol.cameras) {
      hr::Image img = hr::render(sol, cam, ext.get());
      for (float v : img.rgb) ASSERT_TRUE(std::isfinite(v));
    }
  }
}

/// Two near-mirrors (rho_d 0, rho_s 0.9, n = 10^4, the MGF importer's mirror) facing each other 0.2 m
/// apart around a small lamp: light bounces between them near the normal, where every receiver is in
/// a sender's near field and the whole lobe sits in one Haar leaf cell. Each bounce may only lose
/// light. Before the near-field transfer delivered the flux of the receiver's solid angle (it gave a
/// receiver of ~1 sr the value of the one direction toward its centre, the lobe's cell), this scene
/// came out with 3x its emitted power (imbalance -202 % at eps 1e-3, level 3) and its residual grew
/// from 0.2 to 1.4 x the emitted power; the glossy Soda Shoppe diverged the same way.
TEST(GlossyTransport, FacingNearMirrorsCreateNoEnergy) {
  const std::string json = R"({ "materials": { "l": { "emission": [20,20,20] },
      "mirror": { "diffuse": [0,0,0], "specular": [0.9,0.9,0.9], "exponent": 10000 } },
    "objects": [
      { "type": "quad", "material": "l", "vertices": [[0.45,0.1,0.45],[0.55,0.1,0.45],[0.55,0.1,0.55],[0.45,0.1,0.55]] },
      { "type": "quad", "material": "mirror", "vertices": [[0,0,0],[0,0,1],[1,0,1],[1,0,0]] },
      { "type": "quad", "material": "mirror", "vertices": [[0,0.2,0],[1,0.2,0],[1,0.2,1],[0,0.2,1]] } ] })";
  hr::SolverOptions o;
  o.eps = 5e-4;
  o.maxLevel = 4;
  auto ext = makeIs();
  auto s = testutil::solveText(json, o, ext.get());
  ASSERT_TRUE(s.stats.converged);
  EXPECT_FALSE(s.stats.diverged);
  // The energy audit. Created light (absorbed + escaped beyond the emitted power) within 1 % (was
  // +202 %). Either way within 1.5 %: measured 1.11 % lost here (1.14 % at level 5, audit standard
  // error 0.08 %; at level 3 the near field's geometric correction still creates 1.7 %), where the
  // other glossy scenes hold 1 %: a known residual of the near-field model, not hidden by this bar.
  const double emitted = s.stats.emittedW.y, out = s.stats.absorbedW.y + s.stats.escapedW.y;
  EXPECT_LE(out, emitted * 1.01) << "light created";
  expectBalanced(s, 0.015, "facing near-mirrors");
  // Each iteration's change is the light of one more bounce, at most rho_s = 0.9 of the previous
  // one's: never more than the emitted power.
  for (const auto& it : s.stats.history)
    EXPECT_LE(it.residualW, hr::luminance(s.stats.emittedW)) << "iteration " << it.iteration;
  // Per reflection: a leaf reflects at most rho_s of the power it receives (the lobe's albedo is
  // below 1 and falls toward grazing), within the Haar projection's measured power error (at most
  // 3.1e-3, glossy_extension/README.md), held here to 5e-3.
  double received = 0.0, reflected = 0.0;
  for (std::size_t i = 0; i < s.h->elements().size(); ++i) {
    const auto& e = s.h->element(static_cast<std::uint32_t>(i));
    if (!e.leaf() || s.scene.materials[s.h->patches()[e.patch].material].specular.y <= 0.0) continue;
    const hr::NodeId leaf{static_cast<std::uint32_t>(i)};
    const double in = e.area * s.solver->irradiance()[i].y, sent = ext->reflectedPower(leaf).y;
    EXPECT_LE(sent, 0.9 * in * (1.0 + 5e-3) + 1e-12) << "leaf " << i;
    received += in;
    reflected += sent;
  }
  EXPECT_GT(received, 0.0);
  EXPECT_LE(reflected, 0.9 * received * (1.0 + 5e-3));
}

TEST(GlossyTransport, OneAndTwoThreadsGiveTheSameBits) {
  std::string json = readFile(std::string(GHR_SOURCE_DIR) + "/scenes/three_lights.json");
  hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(json, "").settings);
  o.eps = 4e-4;
  std::vector<hr::Rgb> radiosity[2];
  std::string saved[2];
  for (int t = 0; t < 2; ++t) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t + 1));
    auto ext = makeIs();
    auto s = testutil::solveText(json, o, ext.get());
    radiosity[t] = s.solver->radiosity();
    saved[t] = testutil::savedBytes(*ext);
  }
  ASSERT_EQ(radiosity[0].size(), radiosity[1].size());
  EXPECT_EQ(std::memcmp(radiosity[0].data(), radiosity[1].data(), radiosity[0].size() * sizeof(hr::Rgb)), 0);
  EXPECT_EQ(saved[0], saved[1]) << "the extension's distributions, byte for byte";
}

/// Renders a solution from a camera looking at the reflector of the three-lights scene.
hr::Camera atReflector(const hr::Vec3& eye) {
  hr::Camera c;
  c.name = "reflector";
  c.eye = eye;
  c.lookAt = hr::Vec3(0, 0.6, 0.3);
  c.fovYDeg = 30;
  c.width = 96;
  c.height = 72;
  return c;
}

TEST(GlossyTransport, ASavedSolutionRendersAnyCameraAsTheFreshOneDoes) {
  std::string json = readFile(std::string(GHR_SOURCE_DIR) + "/scenes/three_lights.json");
  hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(json, "").settings);
  o.eps = 4e-4;
  auto ext = makeIs();
  auto s = testutil::solveText(json, o, ext.get());
  hr::Solution fresh = hr::makeSolution(s.scene, *s.h, s.solver->radiosity());
  // Streamed into the file as glossyhr solve does.
  fresh.extension = {std::string(ext->name()), ext->formatVersion(), {}, [&](std::ostream& file) { ext->save(file); }};
  const fs::path file = testutil::testDir() / "s.ghrs";
  hr::saveSolution(fresh, file.string());
  hr::Solution loaded = hr::loadSolution(file.string());
  hr::SolutionView view(loaded);
  auto back = adapters::findExtension(loaded.extension.name).make();
  ASSERT_EQ(back->formatVersion(), loaded.extension.version);
  back->load(loaded.extension.bytes, view);
  // Two eyes on the wall's side, seeing the reflector's glossy front and the lamps in it.
  const hr::Vec3 eyes[2] = {hr::Vec3(-0.6, 1.6, -2.6), hr::Vec3(0.6, 1.6, -2.6)};
  hr::Image images[2];
  for (int k = 0; k < 2; ++k) {
    hr::Image a = hr::render(fresh, atReflector(eyes[k]), ext.get()), b = hr::render(loaded, atReflector(eyes[k]), back.get());
    double d2 = 0.0, m = 0.0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) d2 += double(a.rgb[i] - b.rgb[i]) * (a.rgb[i] - b.rgb[i]), m += a.rgb[i];
    ASSERT_GT(m, 0.0);
    EXPECT_LE(std::sqrt(d2 / a.rgb.size()) / (m / a.rgb.size()), 1e-3) << "relative RMSE, eye " << k;
    images[k] = std::move(b);
  }
  // The highlight moves with the eye: the reflector's glossy light (the render less its diffuse
  // part, B / pi) differs between the two eyes on most of the reflector's pixels.
  hr::Image diffuse[2] = {hr::render(loaded, atReflector(eyes[0])), hr::render(loaded, atReflector(eyes[1]))};
  int onReflector = 0, changed = 0;
  for (std::size_t p = 0; p < images[0].objectId.size(); ++p) {
    if (images[0].objectId[p] != 2 || images[1].objectId[p] != 2) continue;
    ++onReflector;
    double g0 = hr::luminance(hr::Rgb(images[0].rgb[3 * p], images[0].rgb[3 * p + 1], images[0].rgb[3 * p + 2]) -
                              hr::Rgb(diffuse[0].rgb[3 * p], diffuse[0].rgb[3 * p + 1], diffuse[0].rgb[3 * p + 2]));
    double g1 = hr::luminance(hr::Rgb(images[1].rgb[3 * p], images[1].rgb[3 * p + 1], images[1].rgb[3 * p + 2]) -
                              hr::Rgb(diffuse[1].rgb[3 * p], diffuse[1].rgb[3 * p + 1], diffuse[1].rgb[3 * p + 2]));
    if (std::abs(g0 - g1) > 0.05 * std::max(g0, g1)) ++changed;
  }
  ASSERT_GT(onReflector, 50);
  EXPECT_GT(changed, onReflector / 2) << changed << " of " << onReflector << " reflector pixels changed";
}

TEST(GlossyTransport, ADiffuseSceneWithTheExtensionIsTheCoreToTheBit) {
  const fs::path dir = testutil::testDir();
  std::string out;
  for (const char* alg : {"diffuse", "is"})
    ASSERT_EQ(testutil::runCli(std::string("solve --eps 1e-3 --seed 5 --quiet --algorithm ") + alg + " -o " + (dir / alg).string(), out), 0) << out;
  for (const char* file : {"front.exr", "front.png", "solution.vtp"})
    EXPECT_EQ(readFile((dir / "diffuse" / file).string()), readFile((dir / "is" / file).string())) << file;
  hr::Solution a = hr::loadSolution((dir / "diffuse" / "solution.ghrs").string()),
               b = hr::loadSolution((dir / "is" / "solution.ghrs").string());
  EXPECT_EQ(b.algorithm, "is");
  EXPECT_TRUE(b.extension.name.empty()) << "an extension that simulates nothing is not loaded";
  ASSERT_EQ(a.elements.size(), b.elements.size());
  for (std::size_t i = 0; i < a.elements.size(); ++i) ASSERT_EQ(a.elements[i].radiosity, b.elements[i].radiosity);
}

}  // namespace

/// A mirror (rho_d 0, rho_s 0.9, n = 1000) under a diffuse card standing 5-35 cm above it, lit by a
/// lamp on the camera's side: the camera sees the card's lit face in the mirror. What each mirror
/// pixel shows follows from the geometry: its reflected eye ray meets the card at a point whose
/// radiance is the card's B / pi there (the solve's own, diffuse, card leaves), and a narrow normalised
/// Phong lobe returns rho_s (n+2)/(n+1) cos(theta_i) of it; a ray that misses the card sees black.
/// Pixels within the lobe's width of the card's outline (where the lobe blurs it) are left out. Every
/// Illumination Sample carries the direction to its sender element's centre and a mirror leaf
/// reflects it alike over its whole area: before the oracle split receivers and senders seen wider
/// than the lobe, the card came out as blobs.
TEST(GlossyTransport, AMirrorReflectsANearCardAsTheGeometrySays) {
  const std::string json = R"({ "materials": { "l": { "emission": [12,12,12] }, "w": { "diffuse": [0.8,0.8,0.8] },
      "mirror": { "diffuse": [0,0,0], "specular": [0.9,0.9,0.9], "exponent": 1000 } },
    "objects": [
      { "type": "quad", "material": "l", "vertices": [[-0.3,1.5,-1.6],[0.3,1.5,-1.6],[0.3,1.5,-1.0],[-0.3,1.5,-1.0]] },
      { "type": "quad", "material": "mirror", "vertices": [[-0.6,0,-0.6],[-0.6,0,0.6],[0.6,0,0.6],[0.6,0,-0.6]] },
      { "type": "quad", "material": "w", "vertices": [[0.2,0.05,0],[-0.2,0.05,0],[-0.2,0.35,0],[0.2,0.35,0]] } ] })";
  constexpr std::uint32_t kMirror = 1, kCard = 2;
  const double exponent = 1000.0, rhoS = 0.9, width = std::sqrt(2.0 / exponent);
  hr::Camera cam;
  cam.name = "mirror";
  cam.eye = hr::Vec3(0, 0.9, -2.2);
  cam.lookAt = hr::Vec3(0, 0.05, 0);
  cam.fovYDeg = 24;
  cam.width = 160;
  cam.height = 120;
  const hr::CameraRays rays(cam);
  // Where a ray from p along r meets the card's lit face (z = 0, facing -z), if it does.
  auto hitCard = [](const hr::Vec3& p, const hr::Vec3& r, hr::Vec3& q) {
    if (r.z <= 0.0 || p.z >= 0.0) return false;
    q = p + (-p.z / r.z) * r;
    return std::abs(q.x) <= 0.2 && q.y >= 0.05 && q.y <= 0.35;
  };
  struct Figures {
    double relRmse = 0.0;
    int card = 0, black = 0;
  };
  auto measure = [&](const std::vector<hr::OptionValue>& options) {
    hr::SolverOptions o;
    o.eps = 2e-4;
    auto ext = makeIs(options);
    auto s = testutil::solveText(json, o, ext.get());
    // The card's radiance at a point: B / pi of its nearest leaf (the solve's diffuse light).
    auto cardRadiance = [&](const hr::Vec3& q) {
      double best = 1e300, L = 0.0;
      for (std::size_t i = 0; i < s.h->elements().size(); ++i) {
        const auto& e = s.h->element(static_cast<std::uint32_t>(i));
        if (!e.leaf() || s.h->patches()[e.patch].object != kCard) continue;
        const double d = glm::length(e.center - q);
        if (d < best) best = d, L = hr::luminance(s.solver->radiosity()[i]) / hr::kPi;
      }
      return L;
    };
    hr::Solution sol = hr::makeSolution(s.scene, *s.h, s.solver->radiosity());
    const hr::Image img = hr::render(sol, cam, ext.get());
    Figures f;
    double d2 = 0.0, sumCard = 0.0;
    int n = 0;
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        const std::size_t p = std::size_t(y) * cam.width + x;
        if (img.objectId[p] != kMirror) continue;
        const hr::Vec3 d = rays.dir(x + 0.5, y + 0.5), at = cam.eye + (-cam.eye.y / d.y) * d, r(d.x, -d.y, d.z);
        // The reflected ray and eight tilted by the lobe's 1/e half-width: all must agree.
        const hr::Vec3 u = glm::normalize(glm::cross(r, hr::Vec3(0, 1, 0))), v = glm::cross(r, u);
        hr::Vec3 q;
        const bool in = hitCard(at, r, q);
        bool edge = false;
        for (int k = 0; k < 8 && !edge; ++k) {
          const double a = k * hr::kPi / 4.0;
          hr::Vec3 qk;
          edge = hitCard(at, glm::normalize(r + width * (std::cos(a) * u + std::sin(a) * v)), qk) != in;
        }
        if (edge) continue;
        const double expected = in ? rhoS * (exponent + 2.0) / (exponent + 1.0) * -d.y * cardRadiance(q) : 0.0;
        const double L = hr::luminance(hr::Rgb(img.rgb[3 * p], img.rgb[3 * p + 1], img.rgb[3 * p + 2]));
        d2 += (L - expected) * (L - expected), ++n;
        if (in) sumCard += expected, ++f.card;
        else ++f.black;
      }
    f.relRmse = f.card > 0 && n > 0 ? std::sqrt(d2 / n) / (sumCard / f.card) : 1e9;
    return f;
  };
  const Figures sharp = measure({}), blurred = measure({{"reflection-refine", "off"}}),
                points = measure({{"sender-extent", "off"}});
  std::printf("mirror: %d card pixels, %d black; reflection rel. RMSE against the geometry %.3f (refinement off: %.3f, "
              "senders as points: %.3f)\n",
              sharp.card, sharp.black, sharp.relRmse, blurred.relRmse, points.relRmse);
  ASSERT_GT(sharp.card, 200);
  ASSERT_GT(sharp.black, 200);
  // Measured 0.084 since senders are reflected as their disks (0.135 as points, which fails this bar;
  // refinement off 0.186, 1.16 before samples were re-aimed at every leaf); what remains is mostly
  // the Haar cells against a lobe of 2.6 degrees and the display's corner values.
  EXPECT_LE(sharp.relRmse, 0.10);
}

/// The glossy Cornell box at a coarse eps (2e-3), gathered and then shot: f(scene text, options, scheme).
template <class F>
void onGlossyCornellAtACoarseEps(F&& f) {
  const std::string json = readFile(std::string(GHR_SOURCE_DIR) + "/scenes/glossy_cornell.json");
  for (hr::Iteration it : {hr::Iteration::Gather, hr::Iteration::Shoot}) {
    hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(json, "glossy_cornell.json").settings);
    o.eps = 2e-3;
    o.iteration = it;
    f(json, o, it == hr::Iteration::Gather ? "gathering" : "shooting");
  }
}

TEST(GlossyTransport, EverySampleALeafReflectsPointsAtItsSenderFromThatLeaf) {
  // Samples the host carries down from a link's receiver (or a cluster above) are re-aimed from each
  // child's centre (hr::aimFrom): at every glossy leaf of the glossy Cornell box, the leaf's centre
  // plus a sample's distance along its direction lands on a node's centre (its sender's) within
  // 0.1 mm, for gathering and shooting. Without the re-aiming, a sample from an ancestor points from
  // the ancestor's centre and misses (the tall block mirrored the short one smeared upward).
  onGlossyCornellAtACoarseEps([](const std::string& json, const hr::SolverOptions& o, const char* scheme) {
    testutil::AimChecker ext;
    testutil::solveText(json, o, &ext);
    std::printf("%s: %llu samples at leaves checked, %llu missed their sender, %llu of unknown distance\n", scheme,
                (unsigned long long)ext.checked.load(), (unsigned long long)ext.missed.load(),
                (unsigned long long)ext.unknown.load());
    EXPECT_GT(ext.checked.load(), 10000u) << scheme;
    EXPECT_EQ(ext.missed.load(), 0u) << scheme;
    EXPECT_EQ(ext.unknown.load(), 0u) << scheme;
  });
}

TEST(GlossyTransport, ReflectionInLayersGivesTheWholeSampleListsAnswer) {
  // The glossy Cornell box (two glossy materials, n 60 and 300) at a coarse eps, solved with the
  // host handing inner elements' samples to the extension once per subtree (Extension::reflectShared;
  // here all of them, near senders too, none re-aimed: testutil::LayersTakingAll) and with every leaf
  // given all of its and its ancestors' samples: every glossy leaf reflects the
  // same power within 1e-4 (merging groups samples per layer instead of per leaf: a few directions
  // move by less than 1/16 of a lobe's width), radiosity within 1e-4; the layers did take most samples.
  // Gathering, and shooting, whose passes reflect in batches (a layer must not outlive its batch, and
  // a leaf whose samples an ancestor took all still adds that layer).
  onGlossyCornellAtACoarseEps([](const std::string& json, const hr::SolverOptions& o, const char* scheme) {
    auto layered = std::make_unique<testutil::LayersTakingAll>();
    testutil::WholeSampleLists whole;
    auto a = testutil::solveText(json, o, layered.get());
    auto b = testutil::solveText(json, o, &whole);
    ASSERT_EQ(a.h->elements().size(), b.h->elements().size()) << scheme;
    testutil::expectLayersTookMostSamples(*layered, whole);
    double worstPower = 0.0, worstB = 0.0;
    const auto& glossyA = static_cast<const glossy::IlluminationSamples&>(*layered);
    for (std::uint32_t i = 0; i < a.h->elements().size(); ++i) {
      const hr::Rgb ba = a.solver->radiosity()[i], bb = b.solver->radiosity()[i];
      worstB = std::max(worstB, hr::maxComponent(glm::abs(ba - bb)) / std::max(1e-9, hr::maxComponent(bb)));
      if (!a.h->element(i).leaf()) continue;
      const auto *la = glossyA.light(hr::NodeId{i}), *lb = whole.light(hr::NodeId{i});
      if (!la && !lb) continue;
      ASSERT_TRUE(la && lb) << scheme << ", element " << i;
      worstPower = std::max(worstPower, hr::maxComponent(glm::abs(la->power - lb->power)) / hr::maxComponent(lb->power));
    }
    std::printf("%s, worst leaf: reflected power %.2e, radiosity %.2e (relative)\n", scheme, worstPower, worstB);
    EXPECT_LT(worstPower, 1e-4) << scheme;
    EXPECT_LT(worstB, 1e-4) << scheme;
  });
}
