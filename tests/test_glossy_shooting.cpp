// Glossy shooting end to end (--algorithm is --iteration shoot, paper §3.4), host and extension
// together: the image agrees with gathering's, energy balances, a shooting pass holds fewer samples
// than a gathering iteration, and the answer does not depend on the thread count. Also the
// Radiance Clustering baseline's image against Illumination Samples' (same bases, same refiner).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <ref/compare.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "helpers.h"
#include "registry.h"
#include "saved_bytes.h"

namespace {

std::string sceneText(const std::string& name) {
  std::ifstream f(std::string(GHR_SOURCE_DIR) + "/scenes/" + name);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::unique_ptr<hr::Extension> make(const char* algorithm) { return adapters::findExtension(algorithm).make(); }

struct Solve {
  std::unique_ptr<hr::Extension> ext;
  testutil::Solved solved;
  hr::Image image;
};

/// Solves a scene file with an extension and renders its first camera.
Solve solve(const std::string& scene, hr::SolverOptions o, const char* algorithm) {
  Solve r;
  r.ext = make(algorithm);
  r.solved = testutil::solveText(sceneText(scene), o, r.ext.get());
  hr::Solution sol = hr::makeSolution(r.solved.scene, *r.solved.h, r.solved.solver->radiosity());
  EXPECT_FALSE(sol.cameras.empty()) << scene;
  r.image = hr::render(sol, sol.cameras.front(), r.ext.get());
  return r;
}

/// Image difference with the light sources left out (both copy their radiance from the scene).
ref::Metrics lightsMasked(const Solve& a, const Solve& b) {
  return ref::compare(a.image, b.image, -1, "A", "B", hr::emitterObjects(a.solved.scene));
}

/// A scene's own settings, with eps replaced when one is given.
hr::SolverOptions optionsOf(const std::string& scene, double eps = 0.0) {
  hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(sceneText(scene), "").settings);
  if (eps > 0.0) o.eps = eps;
  return o;
}

double balance(const testutil::Solved& s, int c) {
  return (s.stats.absorbedW[c] + s.stats.escapedW[c]) / s.stats.emittedW[c];
}

/// A scene solved at its own settings by gathering and by shooting (Illumination Samples), and the
/// two images' difference with the lights left out.
struct ShootAndGather {
  Solve g, s;
  ref::Metrics m;
};
ShootAndGather shootAndGather(const std::string& scene) {
  ShootAndGather r;
  hr::SolverOptions o = optionsOf(scene);
  r.g = solve(scene, o, "is");
  o.iteration = hr::Iteration::Shoot;
  r.s = solve(scene, o, "is");
  r.m = lightsMasked(r.s, r.g);
  std::printf("%s (eps %g): shoot vs gather rel RMSE %.4f, mean ratio %.4f; samples per pass/iteration at most %zu vs "
              "%zu, held at once %zu vs %zu\n",
              scene.c_str(), o.eps, r.m.relRmse, r.m.meanRatio, r.s.solved.stats.peakSamples, r.g.solved.stats.peakSamples,
              r.s.solved.stats.peakSamplesAtOnce, r.g.solved.stats.peakSamples);
  return r;
}

/// The acceptance's bars on a shoot-vs-gather pair: converged, RMSE 1 %, means 0.5 %, energy 1 %.
void expectAgreement(const ShootAndGather& r) {
  ASSERT_TRUE(r.s.solved.stats.converged);
  EXPECT_NEAR(r.m.meanRatio, 1.0, 0.005);
  EXPECT_LT(r.m.relRmse, 0.01);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(balance(r.s.solved, c), 1.0, 0.01) << "channel " << c;
}

// Three lights at its own settings, the acceptance's 1 %. Each disk light is 16 patches. While
// shooters were patches, each sending a sixteenth of a light, shooting refined the receivers as for a
// sixteenth and the images lay 5.0 % apart at eps 1e-4. A cluster all of whose patches shoot now
// shoots as one (shoot.cpp), as gathering sends it, and what was left was seed noise (0.89-1.12 % for
// seeds 1-3, each scheme 0.95 / 1.31 % from itself), most of it the lamps' shadows on the floor at 4
// rays per cluster link; 32 since, as for a one-patch emitter (transfer.cpp): at the scene's eps
// 4e-5, 0.91 / 0.60 / 0.61 % for seeds 1-3 (1.28 / 1.09 / 0.93 % at 3.5e-5 before; docs/results.md).
// This is one seed's draw (the default, 1) of a gap that lies within the schemes' own seed spread
// (gathering 1.02 %, shooting 0.70 % from itself at 4e-5): a change to the random streams can move
// it by that much, and then the seeds are what to look at. Bars: RMSE 1 %, means 0.5 %, energy 1 %.
TEST(GlossyShooting, ThreeLightsImageAgreesWithGathering) { expectAgreement(shootAndGather("three_lights.json")); }

// The glossy sphere at its own settings, the acceptance's 1 % and its sample bound. At the eps it
// had until 2026-12-05 (5e-4) the two schemes' images lay 2.61 % apart (2.67 / 2.89 % for seeds
// 1 / 2), each 1 % from itself with another seed: a bias of two discretisations, not noise, and it
// closes as eps falls (1.32 % at 1.25e-4, 0.98 % at 6.25e-5). At 4e-5, three lights' eps, 0.84 /
// 0.84 / 0.85 % for seeds 1-3, each scheme 0.41 / 0.40 % from itself; against a 4,096-spp reference
// the image without the sphere improved with it (gathering 0.084 -> 0.081, shooting 0.091 -> 0.081;
// docs/results.md). What one pass holds at once is reflected in batches of at most 1024 samples
// (shoot.cpp), where a gathering iteration holds all of its links' samples: the acceptance asks
// for at most a tenth.
TEST(GlossyShooting, GlossySphereImageAgreesWithGatheringAndHoldsFewSamples) {
  const ShootAndGather r = shootAndGather("glossy_sphere.json");
  expectAgreement(r);
  EXPECT_LE(double(r.s.solved.stats.peakSamplesAtOnce), 0.1 * double(r.g.solved.stats.peakSamples));
}

/// three_lights.json with each disk light (16 patches) replaced by a square of the same area in its
/// plane, one patch: both schemes send it as one patch (below).
std::string threeSquareLights() {
  nlohmann::json scene = nlohmann::json::parse(sceneText("three_lights.json"));
  for (auto& o : scene["objects"]) {
    if (o["type"] != "disk") continue;
    const hr::Vec3 c(o["center"][0], o["center"][1], o["center"][2]);
    const hr::Vec3 n = glm::normalize(hr::Vec3(o["normal"][0], o["normal"][1], o["normal"][2]));
    const hr::Vec3 a = std::abs(n.x) < 0.9 ? hr::Vec3(1, 0, 0) : hr::Vec3(0, 1, 0);
    const hr::Vec3 u = glm::normalize(a - n * glm::dot(a, n)), v = glm::cross(n, u);  // u x v = n
    const double h = 0.5 * std::sqrt(hr::kPi) * double(o["radius"]);                   // (2h)^2 = pi r^2
    nlohmann::json quad = {{"type", "quad"}, {"material", o["material"]}, {"vertices", nlohmann::json::array()}};
    const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const auto& k : corner) {
      const hr::Vec3 p = c + h * k[0] * u + h * k[1] * v;
      quad["vertices"].push_back({p.x, p.y, p.z});
    }
    o = quad;
  }
  return scene.dump();
}

// Where the two schemes discretise alike, shooting must agree with gathering as closely as gathering
// agrees with itself. On three_lights.json itself the gap was 5.0 % at its eps 1e-4 (gathering
// against itself 0.9-1.3 %) while shooters were patches: each disk light is 16 patches, which
// gathering sends through cluster links whose bounds refine the receivers 3.4x as finely in its first
// iteration (5,679 elements against shooting's 1,691; cluster shooters since, the test above). With
// each light one patch both refine alike, so a defect of glossy shooting's transport (stale light in
// split children, a final answer that is not the fixed point of its links) shows here as more than
// the seed's own spread. That spread is the bar, not a fixed 1 %: since the shadow term refines the
// lamps' shadows finely, gathering against itself with another seed reads 0.97-1.26 % (seeds 1-4,
// 2026-12-06), and shooting against gathering 1.01-1.27 % with the same seed (0.97-1.49 % for seeds
// 1-6 before emitters kept the shadow term; the fixed 1 % passed for seed 1 alone).
TEST(GlossyShooting, SquareLightsImageAgreesWithGatheringAsGatheringWithItself) {
  const std::string text = threeSquareLights();
  hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(text, "").settings);
  o.eps = 1e-4;  // where the figures above were measured (the scene's eps until it became 4e-5)
  auto run = [&](hr::Iteration it, std::uint32_t seed) {
    o.iteration = it;
    o.seed = seed;
    Solve r;
    r.ext = make("is");
    r.solved = testutil::solveText(text, o, r.ext.get());
    hr::Solution sol = hr::makeSolution(r.solved.scene, *r.solved.h, r.solved.solver->radiosity());
    r.image = hr::render(sol, sol.cameras.front(), r.ext.get());
    return r;
  };
  Solve g = run(hr::Iteration::Gather, 1), s = run(hr::Iteration::Shoot, 1), g2 = run(hr::Iteration::Gather, 2);
  ASSERT_TRUE(s.solved.stats.converged);
  ref::Metrics m = lightsMasked(s, g);
  const double self = lightsMasked(g2, g).relRmse;
  std::printf("three square lights (eps %g): shoot vs gather rel RMSE %.4f (gathering vs itself, seed 2: %.4f), mean "
              "ratio %.4f; elements %zu vs %zu\n",
              o.eps, m.relRmse, self, m.meanRatio, s.solved.h->elements().size(), g.solved.h->elements().size());
  EXPECT_LT(m.relRmse, 1.3 * self);
  EXPECT_LT(m.relRmse, 0.02);
  EXPECT_NEAR(m.meanRatio, 1.0, 0.005);
}

// A shooting pass carries the samples of its shooters' links only, and they are dropped after
// reflection. Our gathering does not pile samples up across iterations (each iteration replaces its
// links' samples), so the gain is smaller than the paper's: with one shooter per pass, at most 4
// samples per pass against 19 per iteration on three lights at eps 4e-4. With the default
// --shoot-fraction 0.1 a pass holds MORE (192): shooters are patches, so the reflector is reached by
// many element links where gathering reaches it through a few cluster links (docs/results.md).
// (What a pass holds at once is bounded separately: it reflects its samples in batches of at most
// 1024, shoot.cpp, stats' samples_peak_at_once; 0.052 of gathering's peak on the glossy sphere.)
TEST(GlossyShooting, APassHoldsFewerSamplesThanAnIteration) {
  hr::SolverOptions o = optionsOf("three_lights.json", 4e-4);
  Solve g = solve("three_lights.json", o, "is");
  o.iteration = hr::Iteration::Shoot;
  o.shootFraction = 1.0;
  o.maxIterations = 2000;
  Solve s = solve("three_lights.json", o, "is");
  ASSERT_TRUE(s.solved.stats.converged);
  std::printf("three lights, one shooter per pass: at most %zu samples per pass vs %zu per iteration (%d passes)\n",
              s.solved.stats.peakSamples, g.solved.stats.peakSamples, s.solved.stats.iterations);
  EXPECT_LE(4 * s.solved.stats.peakSamples, g.solved.stats.peakSamples);
}

TEST(GlossyShooting, OneAndTwoThreadsGiveTheSameBits) {
  hr::SolverOptions o = optionsOf("three_lights.json", 4e-4);
  o.iteration = hr::Iteration::Shoot;
  std::vector<hr::Rgb> radiosity[2];
  std::string saved[2];
  for (int t = 0; t < 2; ++t) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t + 1));
    auto ext = make("is");
    auto s = testutil::solveText(sceneText("three_lights.json"), o, ext.get());
    radiosity[t] = s.solver->radiosity();
    saved[t] = testutil::savedBytes(*ext);
  }
  ASSERT_EQ(radiosity[0].size(), radiosity[1].size());
  EXPECT_EQ(std::memcmp(radiosity[0].data(), radiosity[1].data(), radiosity[0].size() * sizeof(hr::Rgb)), 0);
  EXPECT_EQ(saved[0], saved[1]) << "the extension's distributions, byte for byte";
}

// Radiance Clustering and Illumination Samples differ only in how incident light is reflected
// (immediate push per sample vs all of a leaf's samples at once), so their images should be
// "essentially indistinguishable" (paper §6.3); acceptance: 2 % relative RMSE.
TEST(RadianceClusteringBaseline, ImageAgreesWithIlluminationSamples) {
  hr::SolverOptions o = optionsOf("three_lights.json", 4e-4);
  Solve is = solve("three_lights.json", o, "is");
  Solve rc = solve("three_lights.json", o, "rc");
  ref::Metrics m = lightsMasked(rc, is);
  std::printf("three lights: RC vs IS rel RMSE %.4f, mean ratio %.4f\n", m.relRmse, m.meanRatio);
  EXPECT_LT(m.relRmse, 0.02);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(balance(rc.solved, c), 1.0, 0.01) << "channel " << c;
}

}  // namespace
