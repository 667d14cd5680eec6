// Display reconstruction without bias (issue 10, item 4). The smooth image of a solution must show
// each object as bright as the solution's own leaves do (a flat render: each leaf its radiosity);
// light never blends across objects, materials or emitters, nor from hidden leaves onto visible ones.
// And the image converges to the project's own path tracer as the threshold falls.
#include <gtest/gtest.h>
#include <hr/output.h>
#include <hr/solution.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include "helpers.h"
#include "test_dir.h"

namespace {

/// Mean luminance of the pixels showing each object.
std::map<std::uint32_t, double> objectMeans(const hr::Image& img) {
  std::map<std::uint32_t, std::pair<double, int>> acc;
  for (std::size_t i = 0; i < img.objectId.size(); ++i) {
    if (img.objectId[i] == hr::kNone) continue;
    auto& [sum, n] = acc[img.objectId[i]];
    sum += hr::luminance(hr::Rgb(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]));
    ++n;
  }
  std::map<std::uint32_t, double> out;
  for (const auto& [id, a] : acc) out[id] = a.first / a.second;
  return out;
}

hr::Solution solveToSolution(const std::string& json, double eps) {
  hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(json, "").settings);
  o.eps = eps;
  auto s = testutil::solveText(json, o);
  return hr::makeSolution(s.scene, *s.h, s.solver->radiosity());
}

// Before: the ceiling's leaves hidden 1 mm above the lamp darkened a ring around it (ceiling 1.7 %
// darker smooth than flat, floor 0.6 %). Measured now: within 0.2 % on every object.
TEST(DisplayBias, SmoothShowsEachObjectAsBrightAsItsLeaves) {
  hr::Solution sol = solveToSolution(hr::kDefaultSceneJson, 2e-4);
  const hr::Camera& cam = sol.cameras.at(0);
  hr::Image smooth = hr::render(sol, cam);
  hr::Image flat = hr::render(sol, cam, [&](std::uint32_t leaf, const hr::Vec3&, const hr::Vec3&) {
    return sol.elements[leaf].radiosity / hr::kPi;
  });
  auto ms = objectMeans(smooth), mf = objectMeans(flat);
  ASSERT_EQ(ms.size(), mf.size());
  for (const auto& [id, m] : mf) EXPECT_NEAR(ms[id] / m, 1.0, 0.005) << "object " << id;
}

// A pixel is the average of the light over its area, as the reference's pixels are: where its 3 x 3
// grid straddles an edge it is sampled 9 x 9. A half-space of directions lit 1 W/(m^2 sr) and the rest
// dark, its edge slanted across the image, against 30 x 30 averages: every pixel whose 3 x 3 grid
// straddles the edge is within 1/18 of its lit share (the 9 x 9 grid's step, plus 1/60 for the
// reference's own grid, 90 x 90 where it straddles: 1/180 there), and their RMS error under half that of 3 x 3 alone (taken as a 3x finer
// image of one ray per pixel, box-filtered). An edge that passes between a pixel's grid rows is not
// seen by it and stays as 3 x 3 draws it. Seen failing with the refinement off: RMS 0.034 (0.011 on).
TEST(DisplayBias, AnEdgePixelIsItsAreaAverage) {
  hr::Solution sol = solveToSolution(hr::kDefaultSceneJson, 1e-2);
  hr::Camera cam = sol.cameras.at(0), fine = cam;
  cam.width = 48, cam.height = 36;
  fine.width = 3 * cam.width, fine.height = 3 * cam.height;
  const hr::Vec3 f = glm::normalize(cam.lookAt - cam.eye), r = glm::normalize(glm::cross(f, cam.up));
  const hr::Vec3 a = glm::normalize(r + 0.37 * glm::cross(r, f) + 0.05 * f);  // the edge's plane through the eye
  const hr::DisplayFn half = [&](std::uint32_t, const hr::Vec3&, const hr::Vec3& toEye) {
    return hr::Rgb(glm::dot(-toEye, a) > 0.0 ? 1.0 : 0.0);
  };
  const hr::Image img = hr::render(sol, cam, half), exact = hr::render(sol, cam, half, 30);
  const hr::Image single = hr::render(sol, fine, half, 1);
  double worst = 0.0, se = 0.0, se3 = 0.0;
  int straddling = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const std::size_t i = std::size_t(y) * cam.width + x;
      double lo = 1.0, hi = 0.0, mean3 = 0.0;
      for (int j = 0; j < 9; ++j) {
        const double v = single.rgb[3 * (std::size_t(3 * y + j / 3) * fine.width + 3 * x + j % 3)];
        lo = std::min(lo, v), hi = std::max(hi, v), mean3 += v / 9.0;
      }
      const double e = img.rgb[3 * i], want = exact.rgb[3 * i];
      if (!(hi > lo)) continue;
      worst = std::max(worst, std::abs(e - want)), ++straddling;
      se += (e - want) * (e - want), se3 += (mean3 - want) * (mean3 - want);
    }
  const double rms = std::sqrt(se / std::max(straddling, 1)), rms3 = std::sqrt(se3 / std::max(straddling, 1));
  std::printf("%d pixels straddled by their 3 x 3 grid: worst %.4f, RMS %.4f (3 x 3 alone %.4f)\n", straddling, worst, rms,
              rms3);
  EXPECT_GT(straddling, 20);
  EXPECT_LT(worst, 1.0 / 18.0 + 1.0 / 60.0);
  EXPECT_LT(rms, 0.5 * rms3);
}

// A lamp flush with (coplanar on) a ceiling, and a red tile flush beside a white one: no corner of
// the ceiling or the white tile takes light from the other material or from the lamp, nor from the
// ceiling's leaves that the lamp covers.
TEST(DisplayBias, NeverBlendsAcrossObjectsMaterialsOrEmitters) {
  const char* json = R"({
  "materials": { "w": { "diffuse": [0.7,0.7,0.7] }, "r": { "diffuse": [0.7,0.1,0.1] },
                 "l": { "diffuse": [0.7,0.7,0.7], "emission": [10,10,10] } },
  "objects": [
    { "type": "quad", "material": "w", "vertices": [[0,1,0],[2,1,0],[2,1,2],[0,1,2]] },
    { "type": "quad", "material": "l", "vertices": [[0.75,1,0.75],[1.25,1,0.75],[1.25,1,1.25],[0.75,1,1.25]] },
    { "type": "quad", "material": "w", "vertices": [[0,0,0],[0,0,2],[1,0,2],[1,0,0]] },
    { "type": "quad", "material": "r", "vertices": [[1,0,0],[1,0,2],[2,0,2],[2,0,0]] } ] })";
  hr::Solution sol = solveToSolution(json, 1e-3);
  std::map<std::uint32_t, std::pair<hr::Rgb, hr::Rgb>> range;  // per object: min and max leaf radiosity
  for (const auto& e : sol.elements) {
    if (!e.leaf()) continue;
    const std::uint32_t obj = sol.patches[e.patch].object;
    auto it = range.find(obj);
    if (it == range.end()) it = range.emplace(obj, std::make_pair(hr::Rgb(1e300), hr::Rgb(0.0))).first;
    it->second.first = glm::min(it->second.first, e.radiosity);
    it->second.second = glm::max(it->second.second, e.radiosity);
  }
  ASSERT_EQ(range.size(), 4u);
  for (std::size_t i = 0; i < sol.elements.size(); ++i) {
    const auto& e = sol.elements[i];
    if (!e.leaf()) continue;
    const auto& [lo, hi] = range[sol.patches[e.patch].object];
    for (int k = 0; k < e.poly.n; ++k)
      for (int c = 0; c < 3; ++c) {
        EXPECT_GE(sol.cornerRadiosity[i][k][c], lo[c] * (1 - 1e-9)) << "leaf " << i;
        EXPECT_LE(sol.cornerRadiosity[i][k][c], hi[c] * (1 + 1e-9)) << "leaf " << i;
      }
  }
  // The lamp's light never reaches the ceiling's corners: they stay far below the lamp's pi L_e.
  for (std::size_t i = 0; i < sol.elements.size(); ++i) {
    if (!sol.elements[i].leaf() || sol.patches[sol.elements[i].patch].object != 0) continue;
    for (int k = 0; k < sol.elements[i].poly.n; ++k) EXPECT_LT(sol.cornerRadiosity[i][k].y, 1.0);
  }
}

}  // namespace

namespace {

struct ImageError {
  double meanRatio = 0.0;   // luminance, the lamp left out
  double worstObject = 0.0;  // largest |object mean ratio - 1|
  std::uint32_t worstId = hr::kNone;
};

/// Image a against the reference, the lamp masked with a margin of 2 pixels: the object id comes
/// from a pixel's centre, and a pixel whose edge the lamp (100 times brighter) only touches is its
/// neighbour's by id but the lamp's by value, so that where the 3 x 3 grid and the tracer's samples
/// cover a different sliver of it, the ceiling around the lamp moved by 12 % at 160 x 160.
/// One object's mean luminance in image a over the reference's, on the same pixels.
double objectRatio(const hr::Image& a, const hr::Image& ref, std::uint32_t id) {
  double sa = 0.0, sr = 0.0;
  for (std::size_t i = 0; i < a.objectId.size(); ++i)
    if (a.objectId[i] == id) {
      sa += hr::luminance(hr::Rgb(a.rgb[3 * i], a.rgb[3 * i + 1], a.rgb[3 * i + 2]));
      sr += hr::luminance(hr::Rgb(ref.rgb[3 * i], ref.rgb[3 * i + 1], ref.rgb[3 * i + 2]));
    }
  return sr > 0.0 ? sa / sr : 0.0;
}

ImageError against(const hr::Image& a, const hr::Image& ref, std::uint32_t lamp) {
  std::vector<char> masked(a.objectId.size(), 0);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      if (a.objectId[std::size_t(y) * a.width + x] == lamp)
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            const int u = x + dx, v = y + dy;
            if (u >= 0 && v >= 0 && u < a.width && v < a.height) masked[std::size_t(v) * a.width + u] = 1;
          }
  std::map<std::uint32_t, std::pair<double, double>> acc;
  double sa = 0.0, sr = 0.0;
  for (std::size_t i = 0; i < a.objectId.size(); ++i) {
    const std::uint32_t id = a.objectId[i];
    if (id == hr::kNone || masked[i]) continue;
    const double la = hr::luminance(hr::Rgb(a.rgb[3 * i], a.rgb[3 * i + 1], a.rgb[3 * i + 2]));
    const double lr = hr::luminance(hr::Rgb(ref.rgb[3 * i], ref.rgb[3 * i + 1], ref.rgb[3 * i + 2]));
    sa += la, sr += lr;
    acc[id].first += la, acc[id].second += lr;
  }
  ImageError e;
  e.meanRatio = sa / sr;
  for (const auto& [id, s] : acc)
    if (std::abs(s.first / s.second - 1.0) > e.worstObject) e.worstObject = std::abs(s.first / s.second - 1.0), e.worstId = id;
  return e;
}

// The Cornell box against `glossyhr reference` (512 spp at 160 x 160: the mean's standard error is
// about 1e-4), the lamp masked. Before inner senders sent their children's radiosity fitted where
// the receiver sees them (docs/solver.md, "Display reconstruction") it measured mean ratio 0.990 /
// 0.994 and worst object -2.4 % / -1.3 % at eps 2e-4 / 5e-5; then 0.9954 / 0.9985 with the tall block
// worst at -1.87 % / -0.86 % (its foot 15 % dark: floor leaves straddling the blocks' feet took the
// covered part's darkness into their mean). With radiosity over the open part of such leaves
// (SolverState::open) the tall block is within 0.5 % at both (the check below fails before it); the
// worst object was then the short block, +1.8 % / +0.3 %: its foot and the floor's shadowed crease
// in front of it too bright at eps 2e-4, from penumbra links of the lamp kept on 4 agreeing rays.
// With 32 rays on an emitter's links (transfer.cpp, kEmitterRays) every object is within 1 % at
// both thresholds (tall block -0.84 % / -0.68 %, mean 0.9963 / 0.9971); the 1 % check at 2e-4 fails
// before it. That 1 % at 2e-4 held for seed 1 only, though: against a 2,048-spp reference the short
// block read +0.97 / +0.85 / +1.45 % for seeds 1-3, and since kept links whose visibility the oracle
// read are traced again (refine.cpp, seenPartly) +1.40 / +1.32 / +1.25 % (this test: 1.14 %), while at
// 5e-5 it improved (+0.45 -> +0.30 %). So 2e-4 is held to 1.5 % and 5e-5 to 1 %. ~30 s.
TEST(DisplayBias, CornellConvergesToThePathTracer) {
  auto dir = testutil::testDir();
  std::string json = hr::kDefaultSceneJson;
  const std::string size = "\"width\": 320, \"height\": 320";
  ASSERT_NE(json.find(size), std::string::npos);
  json.replace(json.find(size), size.size(), "\"width\": 160, \"height\": 160");
  std::ofstream(dir / "cb.json") << json;
  const std::string scene = (dir / "cb.json").string();
  std::string text;
  ASSERT_EQ(testutil::runCli("reference " + scene + " --spp 512 --seed 3 --quiet -o " + (dir / "ref").string(), text), 0) << text;
  hr::Image ref = hr::readExr((dir / "ref" / "front.exr").string());
  ImageError err[2];
  double tall[2] = {0.0, 0.0};
  constexpr std::uint32_t kTallBlock = 6;
  const char* eps[2] = {"2e-4", "5e-5"};
  for (int k = 0; k < 2; ++k) {
    const auto out = dir / eps[k];
    ASSERT_EQ(testutil::runCli("solve " + scene + " --eps " + eps[k] + " --quiet -o " + out.string(), text), 0) << text;
    const hr::Image img = hr::readExr((out / "front.exr").string());
    err[k] = against(img, ref, 5);
    tall[k] = objectRatio(img, ref, kTallBlock);
    std::printf("eps %s: mean ratio %.4f, worst object %u: %.2f %%, tall block %.4f\n", eps[k], err[k].meanRatio,
                err[k].worstId, 100 * err[k].worstObject, tall[k]);
  }
  EXPECT_NEAR(err[0].meanRatio, 1.0, 0.005);
  EXPECT_LT(err[0].worstObject, 0.015);
  // The mean is within 0.2 % at both thresholds now (0.9986 / 0.9981): what falls with eps is the
  // worst object's error.
  EXPECT_LT(err[1].worstObject, err[0].worstObject);
  EXPECT_NEAR(err[1].meanRatio, 1.0, 0.005);
  EXPECT_LT(err[1].worstObject, 0.01);
  for (double t : tall) EXPECT_NEAR(t, 1.0, 0.01) << "the tall block's foot: floor leaves straddling it";
}

}  // namespace

namespace {

// A floor lit by a small lamp 0.5 m above it (testutil::kLampOverFloor: the closed form). Its falloff,
// h^2 / r^4 in the small-lamp limit, is convex over most of the floor, where corners averaged from
// leaf means drew it too bright (the leaf's chord above its curve, twice) and the image's error was a
// few leaves' width squared times the curvature: rel. RMSE 0.0445 against the closed form; with the
// corners moved toward each leaf's mean (reconstruct, kMeanPasses) 0.0090. The flat render (each leaf
// its own radiosity) reads 0.0717 at eps 2e-4.
TEST(DisplayBias, AConvexFalloffIsDrawnAtItsMean) {
  hr::Solution sol = solveToSolution(testutil::kLampOverFloor, 2e-4);
  const double eSmooth = testutil::lampOverFloorError(sol, false), eFlat = testutil::lampOverFloorError(sol, true);
  std::printf("floor against the closed form: smooth %.4f, flat %.4f\n", eSmooth, eFlat);
  EXPECT_LT(eSmooth, 0.5 * eFlat);
  EXPECT_LT(eSmooth, 0.02);
}

}  // namespace
