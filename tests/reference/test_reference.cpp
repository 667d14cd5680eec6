// The reference path tracer against closed forms (white furnace, one-bounce point radiance), against
// theory's bounds where no closed form exists (a glossy furnace), against the radiosity solver on a
// diffuse scene, and against itself: its noise estimate must predict the difference of two seeds, and
// a seed fixes the image whatever the thread count. Also the comparison metrics and the CLI's errors.
#include <gtest/gtest.h>
#include <hr/kernel.h>
#include <hr/rng.h>
#include <ref/compare.h>
#include <ref/path_tracer.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../helpers.h"
#include "../test_dir.h"

namespace fs = std::filesystem;

namespace {

using hr::Rgb;
using hr::Vec3;

struct Traced {
  hr::Scene scene;
  std::unique_ptr<ref::PathTracer> pt;
};

Traced load(const std::string& json) {
  Traced s;
  s.scene = hr::parseScene(json, "test.json");
  hr::TessellationReport rep;
  s.pt = std::make_unique<ref::PathTracer>(s.scene, hr::buildPatches(s.scene, rep));
  return s;
}

std::string furnace(const std::string& material) {
  return R"({ "materials": { "g": )" + material + R"( },
    "objects": [ { "type": "box", "material": "g", "min": [0,0,0], "max": [1,1,1], "facing": "inward" } ],
    "cameras": [ { "name": "in", "eye": [0.5,0.5,0.5], "look_at": [0.1,0.3,0.0], "fov_y_deg": 100, "width": 24, "height": 24 } ] })";
}

TEST(Reference, DiffuseFurnaceIsLeOverOneMinusRho) {
  Traced s = load(furnace(R"({ "diffuse": [0.5,0.5,0.5], "emission": [1,1,1] })"));
  ref::Options o;
  o.spp = 64;
  ref::CameraResult r = s.pt->render(s.scene.cameras[0], o);
  EXPECT_NEAR(r.meanLuminance / 2.0, 1.0, 0.01) << "L = Le / (1 - rho) = 2 W/(m^2 sr)";
  EXPECT_LT(r.relStdError, 0.003);
  EXPECT_EQ(r.nonFinite, 0u);
}

TEST(Reference, GlossyFurnaceStaysWithinTheoryBounds) {
  // No closed form: with a directional albedo a(w) the furnace radiance lies between
  // Le / (1 - min a) and Le / (1 - max a); max a = rho_d + rho_s at normal incidence, min a at grazing.
  glossy::Brdf b = glossy::ModifiedPhong{Rgb(0.2), Rgb(0.3), 10.0};
  const Vec3 n(0, 0, 1);
  double aMax = glossy::albedo(b, n, n).x, aMin = glossy::albedo(b, glm::normalize(Vec3(1, 0, 1e-3)), n).x;
  ASSERT_NEAR(aMax, 0.5, 1e-3);
  Traced s = load(furnace(R"({ "diffuse": [0.2,0.2,0.2], "specular": [0.3,0.3,0.3], "exponent": 10, "emission": [1,1,1] })"));
  ref::Options o;
  o.spp = 64;
  ref::CameraResult r = s.pt->render(s.scene.cameras[0], o);
  double lo = 1.0 / (1.0 - aMin), hi = 1.0 / (1.0 - aMax);
  std::printf("glossy furnace: mean %.4f W/(m^2 sr), bounds [%.4f, %.4f]\n", r.meanLuminance, lo, hi);
  EXPECT_GT(r.meanLuminance, lo);
  EXPECT_LT(r.meanLuminance, hi);
  for (std::size_t i = 0; i < r.image.rgb.size(); i += 3) {
    double sigma = std::sqrt(r.variance[i + 1]);
    ASSERT_GT(r.image.rgb[i + 1], lo - 4.0 * sigma);
    ASSERT_LT(r.image.rgb[i + 1], hi + 4.0 * sigma);
  }
}

TEST(Reference, OneBounceRadianceMatchesThePointFormFactor) {
  // Receiver (rho 0.8) under a unit emitter (Le = 1, rho 0) at distance 1: at a receiver point x,
  // L = rho Le F(x -> emitter), with F the exact point-to-polygon form factor.
  Traced s = load(testutil::kParallelPlates);
  const auto& emitter = s.pt->patches()[0];
  for (Vec3 x : {Vec3(0.5, 0.5, 0), Vec3(0.1, 0.2, 0), Vec3(0.9, 0.95, 0)}) {
    double F = hr::pointPolygonFormFactor(x, Vec3(0, 0, 1), emitter.poly, emitter.normal);
    Vec3 org = x + Vec3(0.05, -0.03, 0.2);
    Vec3 dir = glm::normalize(x - org);
    const int N = 40000;
    double sum = 0.0;
    for (int k = 0; k < N; ++k) {
      hr::Rng rng(9, std::uint64_t(k), std::uint64_t(x.x * 1000));
      sum += s.pt->radiance(org, dir, rng, 16).y;
    }
    EXPECT_NEAR(sum / N / (0.8 * F), 1.0, 0.01) << "at " << x.x << "," << x.y;
  }
}

TEST(Reference, AgreesWithTheRadiositySolverOnADiffuseScene) {
  hr::Scene scene = hr::defaultScene();
  hr::Camera cam = scene.cameras[0];
  cam.width = cam.height = 64;
  hr::SolverOptions so = hr::SolverOptions::from(scene.settings);
  auto solved = testutil::solveText(hr::kDefaultSceneJson, so);
  hr::Solution sol = hr::makeSolution(solved.scene, *solved.h, solved.solver->radiosity());
  hr::Image radiosity = hr::render(sol, cam);
  Traced s = load(hr::kDefaultSceneJson);
  ref::Options o;
  o.spp = 128;
  ref::CameraResult r = s.pt->render(cam, o);
  ref::Metrics m = ref::compare(radiosity, r.image), wall = ref::compare(radiosity, r.image, 2);
  std::printf("radiosity (eps %.0e) against the reference (%d spp, +-%.2f %% on the mean): mean ratio %.4f, rel RMSE %.3f"
              " (back wall only: ratio %.4f, rel RMSE %.3f)\n",
              so.eps, r.spp, 100.0 * r.relStdError, m.meanRatio, m.relRmse, wall.meanRatio, wall.relRmse);
  EXPECT_NEAR(m.meanRatio, 1.0, 0.02);
}

TEST(Reference, NoiseEstimatePredictsTheDifferenceOfTwoSeeds) {
  // The lower back of the Cornell box, boxes included, light out of view: the check is a sum over
  // pixels, and when a handful of pixels (the emitter's edges) hold 90 % of the variance it is the
  // chi-square of those few, +-40 % whatever the estimator; here the noise is spread over all.
  Traced s = load(hr::kDefaultSceneJson);
  hr::Camera cam = s.scene.cameras[0];
  cam.width = cam.height = 48;
  cam.lookAt = Vec3(1.0, 0.6, 0.0);
  cam.fovYDeg = 22.0;
  ref::Options o;
  o.spp = 64;
  o.seed = 1;
  ref::CameraResult a = s.pt->render(cam, o);
  o.seed = 2;
  ref::CameraResult b = s.pt->render(cam, o);
  // Summed over pixels, (a - b)^2 and var_a + var_b agree when the variance estimates are honest (a
  // ratio of sums: the mean of per-pixel ratios is biased upward by variances from 8 replicates).
  double d2 = 0.0, v = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 1; i < a.image.rgb.size(); i += 3) {
    double d = a.image.rgb[i] - b.image.rgb[i];
    d2 += d * d;
    v += a.variance[i] + b.variance[i];
    ++n;
  }
  double z2 = d2 / v;
  double dz = (a.meanLuminance - b.meanLuminance) /
              std::hypot(a.relStdError * a.meanLuminance, b.relStdError * b.meanLuminance);
  std::printf("mean normalised squared difference %.3f over %zu pixels; image means differ by %.2f sigma\n", z2, n, dz);
  EXPECT_NEAR(z2, 1.0, 0.1);
  EXPECT_LT(std::abs(dz), 4.0);
}

TEST(Reference, PacketQueriesAgreeWithSingleRays) {
  // The tracer's 16-ray closest-hit batches (including a partial last batch) and shadow batches answer
  // as the single-ray queries do, on the tracer's non-robust scene, for rays from inside the box.
  Traced s = load(hr::kDefaultSceneJson);
  const hr::Visibility& vis = s.pt->visibility();
  const int N = 1000;
  std::vector<Vec3> org(N), dir(N), to(N);
  hr::Rng rng(5, 0);
  for (int i = 0; i < N; ++i) {
    org[i] = Vec3(0.1 + 1.8 * rng.uniform(), 0.1 + 1.8 * rng.uniform(), 0.1 + 1.8 * rng.uniform());
    double z = 2.0 * rng.uniform() - 1.0, phi = 2.0 * glossy::kPi * rng.uniform(), r = std::sqrt(1.0 - z * z);
    dir[i] = Vec3(r * std::cos(phi), r * std::sin(phi), z);
    to[i] = Vec3(0.1 + 1.8 * rng.uniform(), 0.1 + 1.8 * rng.uniform(), 0.1 + 1.8 * rng.uniform());
  }
  std::vector<hr::SurfaceHit> hits(N);
  vis.intersect(org.data(), dir.data(), N - 7, hits.data());
  std::unique_ptr<bool[]> blocked(new bool[N]);
  vis.occluded(org.data(), to.data(), N, blocked.get());
  int hitCount = 0, blockedCount = 0;
  for (int i = 0; i < N - 7; ++i) {
    hr::SurfaceHit one = vis.intersect(org[i], dir[i]);
    ASSERT_EQ(hits[i].hit, one.hit) << i;
    ASSERT_EQ(hits[i].patch, one.patch) << i;
    ASSERT_NEAR(hits[i].t, one.t, 1e-6) << i;
    hitCount += one.hit;
  }
  for (int i = 0; i < N; ++i) {
    ASSERT_EQ(blocked[i], vis.occluded(org[i], to[i])) << i;
    blockedCount += blocked[i];
  }
  std::printf("%d of %d rays hit (the box is open at the front), %d of %d segments blocked\n", hitCount, N - 7,
              blockedCount, N);
  EXPECT_GT(blockedCount, 0);
  EXPECT_LT(blockedCount, N);
}

TEST(Reference, SeedFixesTheImageWhateverTheThreadCount) {
  Traced s = load(hr::kDefaultSceneJson);
  hr::Camera cam = s.scene.cameras[0];
  cam.width = cam.height = 24;
  ref::Options o;
  o.spp = 8;
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    return s.pt->render(cam, o).image.rgb;
  };
  auto one = run(1), two = run(2);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(float)), 0);
}

TEST(Compare, MetricsOnKnownImages) {
  hr::Image b;
  b.width = 4, b.height = 2;
  b.rgb.assign(24, 1.0f);
  b.objectId = {0, 0, 0, 0, 1, 1, 1, 1};
  hr::Image a = b;
  ref::Metrics same = ref::compare(a, b);
  EXPECT_EQ(same.relRmse, 0.0);
  EXPECT_EQ(same.meanRatio, 1.0);
  for (std::size_t i = 12; i < 24; ++i) a.rgb[i] = 1.5f;  // object 1 is 50 % brighter
  ref::Metrics m = ref::compare(a, b);
  EXPECT_NEAR(m.meanRatio, 1.25, 1e-6);
  EXPECT_NEAR(m.relRmse, std::sqrt(0.5 * 0.25), 1e-6);
  EXPECT_NEAR(m.meanRelError, 0.25, 1e-6);
  EXPECT_NEAR(m.maxAbsError, 0.5, 1e-6);
  EXPECT_NEAR(ref::compare(a, b, 1).meanRatio, 1.5, 1e-6);
  EXPECT_NEAR(ref::compare(a, b, 0).relRmse, 0.0, 1e-12);
  hr::Image small = b;
  small.width = 2;
  EXPECT_THROW(ref::compare(small, b), hr::InputError);
  hr::Image noIds = b;
  noIds.objectId.clear();
  EXPECT_THROW(ref::compare(noIds, b, 1), hr::InputError);
  EXPECT_THROW(ref::compare(a, b, 7), hr::InputError) << "no pixel of object 7";
}

// The reference's noise taken out of the error (compare --reference-variance): a reference made
// of a known image plus Gaussian noise of a known variance per pixel. A candidate equal to the
// known image must come out near 0 error though the raw rel. RMSE is the noise's; one 10 % too
// bright near 0.10. Noise drawn once for all channels (fully correlated) is matched by the range's
// low end, drawn per channel (independent) by its high end. 80 000 pixels: the estimates' own
// spread is ~1 % of the noise.
TEST(Compare, ReferenceNoiseIsTakenOutOfTheError) {
  const int W = 400, H = 200;
  const double sigma = 0.2;  // per channel, around a true value of 1
  hr::Rng rng(11, 0);
  auto gauss = [&] {
    const double u = std::max(rng.uniform(), 1e-300), v = rng.uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * hr::kPi * v);
  };
  for (bool correlated : {true, false}) {
    SCOPED_TRACE(correlated ? "channels fully correlated" : "channels independent");
    hr::Image truth, ref, var;
    for (hr::Image* im : {&truth, &ref, &var}) im->width = W, im->height = H, im->rgb.assign(3 * W * H, 0.0f);
    for (int i = 0; i < W * H; ++i) {
      const double shared = gauss();
      for (int c = 0; c < 3; ++c) {
        const double t = 1.0 + 0.5 * double(i % 7) / 7.0;  // some structure
        truth.rgb[3 * i + c] = float(t);
        ref.rgb[3 * i + c] = float(t + sigma * (correlated ? shared : gauss()));
        var.rgb[3 * i + c] = float(sigma * sigma);
      }
    }
    ref::Metrics m = ref::compare(truth, ref);
    ref::addReferenceNoise(m, truth, ref, var, -1, {}, "var");
    ASSERT_TRUE(m.noiseKnown);
    EXPECT_GT(m.relRmse, 0.1) << "the raw error is the reference's noise";
    const double truthError = correlated ? m.relRmseDenoisedLo : m.relRmseDenoisedHi;
    EXPECT_LT(truthError, 0.03) << "a perfect candidate";
    hr::Image bright = truth;
    for (float& v : bright.rgb) v *= 1.1f;
    ref::Metrics b = ref::compare(bright, ref);
    ref::addReferenceNoise(b, bright, ref, var, -1, {}, "var");
    const double meanTruth = 1.0 + 0.5 * 3.0 / 7.0;  // mean of t over i % 7
    double rms = 0.0;
    for (int k = 0; k < 7; ++k) rms += (1.0 + 0.5 * k / 7.0) * (1.0 + 0.5 * k / 7.0) / 7.0;
    EXPECT_NEAR(correlated ? b.relRmseDenoisedLo : b.relRmseDenoisedHi, 0.1 * std::sqrt(rms) / meanTruth, 0.01);
  }
  hr::Image wrong;
  wrong.width = 3, wrong.height = 1, wrong.rgb.assign(9, 0.0f);
  hr::Image one = wrong;
  one.rgb.assign(9, 1.0f);
  ref::Metrics m;
  EXPECT_THROW(ref::addReferenceNoise(m, one, one, hr::Image{}, -1, {}, "var"), hr::InputError) << "sizes differ";
}

TEST(ReferenceCli, BadInputIsRefusedAndNothingWritten) {
  fs::path out = testutil::testDir() / "ref_cli";
  fs::remove_all(out);
  std::string text;
  EXPECT_NE(testutil::runCli("reference -o " + out.string() + " --spp 4 --time-s 1", text), 0);
  EXPECT_NE(text.find("alternatives"), std::string::npos) << text;
  EXPECT_NE(testutil::runCli("reference -o " + out.string() + " --spp 0", text), 0);
  EXPECT_NE(text.find("--spp"), std::string::npos) << text;
  EXPECT_FALSE(fs::exists(out));
  // Two EXRs of different sizes.
  hr::Image a, b;
  a.width = a.height = 2;
  a.rgb.assign(12, 1.0f);
  b.width = 3, b.height = 2;
  b.rgb.assign(18, 1.0f);
  fs::create_directories(out);
  hr::writeExr(a, (out / "a.exr").string());
  hr::writeExr(b, (out / "b.exr").string());
  EXPECT_NE(testutil::runCli("compare " + (out / "a.exr").string() + " " + (out / "b.exr").string() + " -o " +
                                 (out / "d.png").string(), text), 0);
  EXPECT_NE(text.find("same size"), std::string::npos) << text;
  EXPECT_FALSE(fs::exists(out / "d.png"));
  fs::remove_all(out);
}

}  // namespace

namespace {

// One sample per pixel is an unbiased image like any other (it came out black when pixels with fewer
// than two samples were skipped); only its variance is unknown, and says so.
TEST(Reference, OneSamplePerPixelRequestedGivesAnUnbiasedImageWithItsNoise) {
  // Samples come in rounds of 8 independently scrambled replicates (the variance is their spread),
  // so --spp 1 renders 8 per pixel: never a black image, never an unknown variance.
  const std::string scene = R"({ "materials": { "e": { "emission": [1,1,1] }, "r": { "diffuse": [0.8,0.8,0.8] } },
    "objects": [
      { "type": "quad", "material": "e", "vertices": [[0,0,1],[0,1,1],[1,1,1],[1,0,1]] },
      { "type": "quad", "material": "r", "vertices": [[-1,-1,0],[2,-1,0],[2,2,0],[-1,2,0]] } ],
    "cameras": [ { "name": "c", "eye": [0.5,-1.5,0.5], "look_at": [0.5,0.5,0.2], "fov_y_deg": 70, "width": 64, "height": 48 } ] })";
  Traced s = load(scene);
  ref::Options one, many;
  one.spp = 1, many.spp = 64;
  ref::CameraResult r1 = s.pt->render(s.scene.cameras[0], one), r64 = s.pt->render(s.scene.cameras[0], many);
  EXPECT_EQ(r1.spp, 8);
  const double se1 = r1.relStdError * r1.meanLuminance, se64 = r64.relStdError * r64.meanLuminance;
  ASSERT_GT(se1, 0.0);
  ASSERT_GT(se64, 0.0);
  EXPECT_NEAR(r1.meanLuminance, r64.meanLuminance, 4.0 * std::hypot(se1, se64))
      << "means " << r1.meanLuminance << " vs " << r64.meanLuminance << ", noise " << se1;
  // Through the command line: stats.json says how many samples were taken and their noise.
  const fs::path dir = testutil::testDir();
  std::ofstream(dir / "s.json") << scene;
  std::string text;
  ASSERT_EQ(testutil::runCli("reference " + (dir / "s.json").string() + " --spp 1 --quiet -o " + (dir / "out").string(), text), 0) << text;
  std::ifstream in(dir / "out" / "stats.json");
  nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["cameras"][0]["spp"], 8);
  EXPECT_GT(j["cameras"][0]["rel_std_error_of_mean"].get<double>(), 0.0);
  EXPECT_GT(j["cameras"][0]["image_mean_luminance"].get<double>(), 0.0);
}

}  // namespace
