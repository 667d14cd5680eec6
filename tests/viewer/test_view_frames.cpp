// Frames of `glossyhr view --walkthrough` (run under xvfb-run) against the stills' ground truth:
// (1) a viewer frame agrees with `glossyhr render` of the same camera (relative RMSE of luminance,
// light sources masked), at the solve's camera with the default exposure and at a camera that sees
// the highlights; (2) a walkthrough with two eye positions: at both, every pixel showing a diffuse
// surface (away from edges) shows that surface point's eye-independent B / pi, within 1/255, while
// over the highlight the reflector's pixels show what the new eye sees there, which differs from what
// the first eye saw at the same points by more than a stated luminance.
#include <filesystem>
#include <fstream>

#include "test_dir.h"
#include "view_fixture.h"

namespace fs = std::filesystem;

namespace {

using namespace viewtest;

std::string pathJson(const std::vector<hr::Camera>& cams, int w, int h) {
  std::string s = "{\"fps\": 1, \"width\": " + std::to_string(w) + ", \"height\": " + std::to_string(h) + ", \"keyframes\": [";
  auto v = [](const hr::Vec3& x) { return "[" + std::to_string(x.x) + "," + std::to_string(x.y) + "," + std::to_string(x.z) + "]"; };
  for (std::size_t i = 0; i < cams.size(); ++i)
    s += std::string(i ? ", " : "") + "{\"time\": " + std::to_string(i) + ", \"eye\": " + v(cams[i].eye) + ", \"look_at\": " +
         v(cams[i].lookAt) + ", \"up\": " + v(cams[i].up) + ", \"fov_y_deg\": " + std::to_string(cams[i].fovYDeg) + "}";
  return s + "]}";
}

/// Cameras as the path file holds them (6 decimals), so that the ground truth uses the same ones.
hr::Camera rounded(hr::Camera c) {
  auto r = [](hr::Vec3 v) { return hr::Vec3(std::stod(std::to_string(v.x)), std::stod(std::to_string(v.y)), std::stod(std::to_string(v.z))); };
  c.eye = r(c.eye), c.lookAt = r(c.lookAt), c.up = r(c.up);
  return c;
}

/// Renders the cameras as a walkthrough (one frame each) and reads the frames back.
std::vector<Png> viewerFrames(const std::vector<hr::Camera>& cams, const std::string& extra = "") {
  fs::path dir = testutil::testDir();
  std::ofstream(dir / "path.json") << pathJson(cams, cams[0].width, cams[0].height);
  std::string out;
  int rc = runCli("view " + kThreeLights + " --walkthrough " + (dir / "path.json").string() + " --frames " + (dir / "frames").string() +
                      " --quiet " + extra,
                  out);
  EXPECT_EQ(rc, 0) << out;
  std::vector<Png> frames;
  for (std::size_t i = 0; i < cams.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05zu.png", i);
    frames.push_back(readPng((dir / "frames" / name).string()));
    EXPECT_EQ(frames.back().width, cams[0].width);
  }
  return frames;
}

/// Relative RMSE of luminance between a and b (b the reference), over pixels not showing or touching
/// a light source.
double relRmse(const Png& a, const Png& b, const std::vector<PixelTruth>& truth) {
  double se = 0.0, sum = 0.0;
  std::size_t n = 0;
  for (int y = 0; y < b.height; ++y)
    for (int x = 0; x < b.width; ++x) {
      bool light = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          int xx = std::clamp(x + dx, 0, b.width - 1), yy = std::clamp(y + dy, 0, b.height - 1);
          light = light || truth[std::size_t(yy) * b.width + xx].emitter;
        }
      if (light) continue;
      double ya = luminance8(a.at(x, y)), yb = luminance8(b.at(x, y));
      se += (ya - yb) * (ya - yb);
      sum += yb;
      ++n;
    }
  return n && sum > 0.0 ? std::sqrt(se / double(n)) / (sum / double(n)) : 1.0;
}

TEST(ViewFrames, AgreesWithRenderAtTheSolveCamera) {
  const auto& l = threeLights();
  const hr::Camera cam = rounded(l.sol.cameras.at(0));
  std::vector<Png> v = viewerFrames({cam});
  fs::path still = testutil::testDir() / "render.png";
  std::string out;
  ASSERT_EQ(runCli("render " + kThreeLights + " --camera " + cam.name + " -o " + still.string() + " --quiet", out), 0) << out;
  Png r = readPng(still.string());
  ASSERT_EQ(r.width, v[0].width);
  keep(v[0], "agree_overview_viewer");
  keep(r, "agree_overview_render");
  double e = relRmse(v[0], r, pixelTruth(l.sol, l.ext.get(), cam));
  RecordProperty("relative_rmse_x1e4", int(e * 1e4));
  std::printf("relative RMSE of luminance, viewer vs glossyhr render, camera %s: %.4f\n", cam.name.c_str(), e);
  EXPECT_LE(e, 0.03);
}

TEST(ViewFrames, AgreesWithRenderWhereTheHighlightsAre) {
  const auto& l = threeLights();
  const hr::Camera cam = rounded(camera({0.1, 1.3, -2.0}, {0.0, 0.6, 0.3}, 320, 240));
  hr::Image img = hr::render(l.sol, cam, l.ext.get());
  const double exposure = hr::pngExposure(img);
  char flag[64];
  std::snprintf(flag, sizeof flag, "--exposure %.17g", exposure);
  std::vector<Png> v = viewerFrames({cam}, flag);
  Png r{cam.width, cam.height, {}};
  for (float x : img.rgb) r.rgb.push_back(hr::toneMap8(x, exposure));
  double e = relRmse(v[0], r, pixelTruth(l.sol, l.ext.get(), cam));
  keep(v[0], "agree_highlight_viewer");
  keep(r, "agree_highlight_render");
  RecordProperty("relative_rmse_x1e4", int(e * 1e4));
  std::printf("relative RMSE of luminance, viewer vs hr::render, highlight camera: %.4f\n", e);
  EXPECT_LE(e, 0.03);
}

TEST(ViewFrames, TwoEyesMoveTheHighlightNotTheDiffuseLight) {
  const auto& l = threeLights();
  const hr::Vec3 at(0.0, 0.6, 0.3);
  const hr::Camera a = rounded(camera({-0.6, 1.3, -2.0}, at, 240, 180)), b = rounded(camera({0.6, 1.3, -2.0}, at, 240, 180));
  const double exposure = 20.0;  // fixed for the session, whatever the eye
  std::vector<Png> f = viewerFrames({a, b}, "--exposure 20");
  keep(f[0], "two_eyes_a");
  keep(f[1], "two_eyes_b");
  hr::ExtensionDisplay seenFromA(l.sol, *l.ext), seenFromB(l.sol, *l.ext);
  seenFromA.update(a.eye), seenFromB.update(b.eye);
  auto diffuse = [&](const PixelTruth& p) { return hr::interpolate(l.sol, p.leaf, p.point) / hr::kPi; };
  // Diffuse pixels at both eyes: the tone-mapped B / pi of the points shown, within 1/255.
  for (int k = 0; k < 2; ++k) {
    const hr::Camera& cam = k ? b : a;
    SampleTruth t = sampleTruth(l.sol, l.ext.get(), cam);
    int worst = 0;
    std::size_t n = 0;
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        if (!t.uniform(x, y, false)) continue;
        auto want = stillPixel(t, x, y, exposure, diffuse);
        for (int c = 0; c < 3; ++c) {
          int diff = std::abs(int(f[k].at(x, y)[c]) - int(want[std::size_t(c)]));
          if (diff > 1 && worst <= 1) std::printf("eye %d: pixel (%d, %d) differs by %d\n", k, x, y, diff);
          worst = std::max(worst, diff);
        }
        ++n;
      }
    EXPECT_GT(n, std::size_t(cam.width * cam.height / 4)) << "most of the frame shows diffuse surfaces";
    EXPECT_LE(worst, 1) << "eye " << k << ": a diffuse pixel differs from its surface points' B/pi by more than 1/255";
    RecordProperty("diffuse_worst_255_eye" + std::to_string(k), worst);
    std::printf("eye %d: %zu diffuse pixels, worst difference %d/255\n", k, n, worst);
  }
  // The reflector at eye B: its pixels show what B sees; over the spot, that differs from what A saw there.
  SampleTruth t = sampleTruth(l.sol, l.ext.get(), b);
  double peak = 0.0;
  for (const PixelTruth& p : t.big)
    if (p.hit && p.front && p.glossy)
      peak = std::max({peak, hr::luminance(seenFromA.radiance(p.leaf, p.point)), hr::luminance(seenFromB.radiance(p.leaf, p.point))});
  ASSERT_GT(peak, 0.0) << "the reflector shows a highlight from one of the eyes";
  double change = 0.0;
  std::size_t spot = 0, reflector = 0, matches = 0;
  for (int y = 0; y < b.height; ++y)
    for (int x = 0; x < b.width; ++x) {
      if (!t.uniform(x, y, true)) continue;
      auto fromB = [&](const PixelTruth& p) { return diffuse(p) + seenFromB.radiance(p.leaf, p.point); };
      auto fromA = [&](const PixelTruth& p) { return diffuse(p) + seenFromA.radiance(p.leaf, p.point); };
      auto wantB = stillPixel(t, x, y, exposure, fromB), wasA = stillPixel(t, x, y, exposure, fromA);
      ++reflector;
      bool match = true;
      for (int c = 0; c < 3; ++c) match = match && std::abs(int(f[1].at(x, y)[c]) - int(wantB[std::size_t(c)])) <= 1;
      matches += match;
      const PixelTruth& centre = t.sample(x, y, kK * kK / 2);
      if (std::max(hr::luminance(seenFromA.radiance(centre.leaf, centre.point)), hr::luminance(seenFromB.radiance(centre.leaf, centre.point))) <
          0.1 * peak)
        continue;
      ++spot;
      change += std::abs(luminance8(f[1].at(x, y)) - luminance8(wasA.data()));
    }
  ASSERT_GT(spot, 50u) << "the spot covers some pixels";
  change /= double(spot);
  std::printf("reflector: %zu pixels, %zu match eye B within 1/255; spot %zu pixels, mean luminance change %.4f\n", reflector,
              matches, spot, change);
  RecordProperty("spot_mean_luminance_change_x1e4", int(change * 1e4));
  EXPECT_GE(double(matches), 0.99 * double(reflector)) << "the reflector shows what eye B sees";
  EXPECT_GE(change, 0.1) << "the highlight moved with the eye (linear display luminance, 0..1)";
}

}  // namespace
