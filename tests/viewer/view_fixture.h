// Shared scaffolding of the viewer's tests: the three-lights solution (solved once per ctest run by
// the fixture test in CMakeLists.txt, with the Illumination Samples extension), its extension loaded
// back as `glossyhr view` loads it, PNG reading, luminance, and per-pixel ground truth: for each pixel
// centre, the surface point a ray from the camera hits, its leaf and whether the extension simulates it.
#pragma once
#include <gtest/gtest.h>
#include <hr/camera.h>
#include <hr/extension_display.h>
#include <hr/output.h>
#include <hr/solution_view.h>
#include <hr/visibility.h>
#include <stb/stb_image.h>

#include <array>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "extension_cli.h"

namespace viewtest {

inline const std::string kThreeLights = GHR_THREE_LIGHTS;  // solution.ghrs
inline const std::string kSource = GHR_SOURCE_DIR;

struct Loaded {
  hr::Solution sol;
  std::unique_ptr<hr::SolutionView> view;
  std::unique_ptr<hr::Extension> ext;
};

/// The three-lights solution and its extension (loaded once per test process).
inline const Loaded& threeLights() {
  static Loaded* l = [] {
    auto* x = new Loaded;
    x->sol = hr::loadSolution(kThreeLights);
    x->view = std::make_unique<hr::SolutionView>(x->sol);
    x->ext = loadExtension(x->sol, *x->view, kThreeLights);
    return x;
  }();
  return *l;
}

struct Png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  const unsigned char* at(int x, int y) const { return &rgb[3 * (std::size_t(y) * width + x)]; }
};

inline Png readPng(const std::string& path) {
  Png p;
  int n = 0;
  unsigned char* d = stbi_load(path.c_str(), &p.width, &p.height, &n, 3);
  if (!d) return p;
  p.rgb.assign(d, d + std::size_t(p.width) * p.height * 3);
  stbi_image_free(d);
  return p;
}

/// Writes a frame into GHR_KEEP_SHOTS (when set) for a person to look at.
inline void keep(const Png& p, const std::string& name) {
  if (const char* dir = std::getenv("GHR_KEEP_SHOTS")) hr::writePng8(p.rgb, p.width, p.height, std::string(dir) + "/" + name + ".png");
}

/// Linear luminance of an 8-bit sRGB pixel (the sRGB curve undone), in [0, 1].
inline double luminance8(const unsigned char* px) {
  auto lin = [](unsigned char c) {
    double v = c / 255.0;
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
  };
  return 0.2126 * lin(px[0]) + 0.7152 * lin(px[1]) + 0.0722 * lin(px[2]);
}

/// What one pixel centre shows.
struct PixelTruth {
  bool hit = false, front = false, glossy = false, emitter = false;
  std::uint32_t leaf = hr::kNone, object = hr::kNone;
  hr::Vec3 point{0.0};
};

inline std::vector<PixelTruth> pixelTruth(const hr::Solution& s, const hr::Extension* ext, const hr::Camera& cam) {
  hr::Visibility vis(s.patches);
  hr::CameraRays rays(cam);
  std::vector<PixelTruth> out(std::size_t(cam.width) * cam.height);
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      hr::Vec3 d = rays.dir(x + 0.5, y + 0.5);
      hr::SurfaceHit h = vis.intersect(cam.eye, d);
      PixelTruth& t = out[std::size_t(y) * cam.width + x];
      if (!h.hit) continue;
      const hr::Patch& p = s.patches[h.patch];
      const hr::Material& m = s.materials[p.material];
      t.hit = true;
      t.front = glm::dot(p.normal, d) < 0.0;
      t.object = p.object;
      t.point = cam.eye + h.t * d;
      t.leaf = hr::locateLeaf(s, h.patch, t.point);
      t.glossy = ext && ext->simulates({m.diffuse, m.specular, m.exponent, m.emission});
      t.emitter = hr::maxComponent(m.emission) > 0.0;
    }
  return out;
}

/// Samples per pixel and axis of the viewer's stills and of hr::render.
inline constexpr int kK = 3;

/// What each of a pixel's k x k samples shows: pixelTruth of the camera at k times the size (its pixel
/// centres are exactly the samples' positions). samples(x, y, s) is sample s of pixel (x, y).
struct SampleTruth {
  int width = 0, height = 0;
  std::vector<PixelTruth> big;
  const PixelTruth& sample(int x, int y, int s) const {
    return big[std::size_t(y * kK + s / kK) * std::size_t(width * kK) + std::size_t(x * kK + s % kK)];
  }
  /// All samples show the front of one object, of the given kind (glossy or diffuse), not a light.
  bool uniform(int x, int y, bool glossy) const {
    const PixelTruth& a = sample(x, y, 0);
    for (int s = 0; s < kK * kK; ++s) {
      const PixelTruth& b = sample(x, y, s);
      if (!b.hit || !b.front || b.emitter || b.glossy != glossy || b.object != a.object) return false;
    }
    return true;
  }
};

inline SampleTruth sampleTruth(const hr::Solution& s, const hr::Extension* ext, hr::Camera cam) {
  SampleTruth t{cam.width, cam.height, {}};
  cam.width *= kK, cam.height *= kK;
  t.big = pixelTruth(s, ext, cam);
  return t;
}

/// A pixel's tone-mapped value as hr::render makes it: the mean of L over its samples, then the curve.
template <class F>
std::array<unsigned char, 3> stillPixel(const SampleTruth& t, int x, int y, double exposure, F L) {
  hr::Rgb sum(0.0);
  for (int s = 0; s < kK * kK; ++s) sum += L(t.sample(x, y, s));
  sum /= double(kK * kK);
  return {hr::toneMap8(sum.x, exposure), hr::toneMap8(sum.y, exposure), hr::toneMap8(sum.z, exposure)};
}

/// Runs the glossyhr binary (stderr folded in); returns its exit code (-1 when it did not exit). A
/// command that wrongly opens the interactive window is stopped after 120 s (exit 124), not waited for.
inline int runCli(const std::string& args, std::string& output, const std::string& env = "") {
  std::string cmd = env + (env.empty() ? "" : " ") + "/usr/bin/timeout 120 " + std::string(GHR_BINARY) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return -1;
  output.clear();
  std::array<char, 512> buf;
  while (fgets(buf.data(), buf.size(), p)) output += buf.data();
  int st = pclose(p);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

inline hr::Camera camera(hr::Vec3 eye, hr::Vec3 at, int w = 200, int h = 150, double fov = 45.0) {
  hr::Camera c;
  c.name = "test";
  c.eye = eye, c.lookAt = at, c.fovYDeg = fov, c.width = w, c.height = h;
  return c;
}

}  // namespace viewtest
