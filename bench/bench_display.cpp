// The viewer's per-frame glossy re-evaluation alone (hr::ExtensionDisplay::update, paper §5.2), in one
// run: real solutions of a scene (default: the three-lights room) solved with the Illumination Samples
// extension in each basis (Haar, tetrahedron level 3, spherical harmonics of order 8 and 16), their
// glossy leaves each cut into k x k sub-leaves that carry the leaf's own distribution, so that the
// display has about 10k, 100k and 1M glossy vertices with the solution's distributions and geometry;
// each timed over consecutive frames of a walkthrough (30 fps) on one thread and on all threads, with
// the angle threshold 0 (every vertex every frame) and 2 degrees. Printed: ms per frame (wall; the
// one-thread rows also CPU time: the machine may be shared), the slowest frame, vertices updated per frame, and the ratios Haar / SH-16,
// one thread / all threads, threshold 0 / threshold 2 degrees.
//
// usage: bench_display [--scene S.json] [--walkthrough P.json] [--basis haar,tetra,sh8,sh16]
//                      [--sizes 10000,100000,1000000] [--frames N]
#include <hr/extension_display.h>
#include <hr/solver.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <sstream>

#include "camera_path.h"
#include "registry.h"

namespace {

struct Basis {
  std::string name;
  std::vector<hr::OptionValue> options;
};

const std::map<std::string, Basis> kBases = {
    {"haar", {"haar", {{"basis", "haar"}}}},
    {"tetra", {"tetra level 3", {{"basis", "tetra"}, {"tetra-level", "3"}}}},
    {"sh8", {"sh order 8", {{"basis", "sh"}, {"sh-order", "8"}}}},
    {"sh16", {"sh order 16", {{"basis", "sh"}, {"sh-order", "16"}}}},
};

struct Solved {
  hr::Scene scene;
  std::unique_ptr<hr::Hierarchy> h;
  std::unique_ptr<hr::Visibility> vis;
  std::unique_ptr<hr::Extension> ext;
  hr::Solution sol;
  double seconds = 0.0;
};

Solved solve(const std::string& path, const Basis& b) {
  Solved s;
  s.scene = hr::loadScene(path);
  hr::TessellationReport rep;
  s.h = std::make_unique<hr::Hierarchy>(hr::buildPatches(s.scene, rep));
  s.vis = std::make_unique<hr::Visibility>(s.h->patches());
  s.ext = adapters::findExtension("is").make();
  s.ext->configure(b.options);
  hr::Solver solver(s.scene, *s.h, *s.vis, hr::SolverOptions::from(s.scene.settings), s.ext.get());
  auto t0 = std::chrono::steady_clock::now();
  solver.solve();
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  s.sol = hr::makeSolution(s.scene, *s.h, solver.radiosity());
  return s;
}

/// The solution's extension seen through finer leaves: leaf k of the refined solution answers with
/// the distribution of the real leaf it was cut from (same patch, so the same plane and frame).
class Refined : public hr::Extension {
 public:
  Refined(const hr::Extension& inner, std::vector<std::uint32_t> parent) : inner_(inner), parent_(std::move(parent)) {}
  std::string_view name() const override { return "refined"; }
  bool simulates(const hr::MaterialInfo& m) const override { return inner_.simulates(m); }
  hr::Rgb radiance(hr::NodeId leaf, const hr::Vec3& toEye) const override {
    return inner_.radiance(hr::NodeId{parent_[leaf.index()]}, toEye);
  }

 private:
  const hr::Extension& inner_;
  std::vector<std::uint32_t> parent_;
};

/// The glossy leaves of s cut into k x k (quads bilinearly, triangles into k^2 similar ones).
hr::Solution refine(const hr::Solution& s, const hr::Extension& ext, int k, std::vector<std::uint32_t>& parent) {
  hr::Solution f;
  f.patches = s.patches;
  f.materials = s.materials;
  for (std::uint32_t i = 0; i < s.elements.size(); ++i) {
    const hr::SolutionElement& e = s.elements[i];
    const hr::Material& m = s.materials[s.patches[e.patch].material];
    if (!e.leaf() || !ext.simulates({m.diffuse, m.specular, m.exponent, m.emission})) continue;
    const hr::Vec3* v = e.poly.v.data();
    auto add = [&](std::initializer_list<hr::Vec3> pts) {
      hr::SolutionElement c;
      c.patch = e.patch;
      c.poly.n = int(pts.size());
      int j = 0;
      for (const hr::Vec3& p : pts) c.poly.v[std::size_t(j++)] = p;
      f.elements.push_back(c);
      parent.push_back(i);
    };
    for (int a = 0; a < k; ++a)
      for (int b = 0; b < k; ++b) {
        double u0 = double(a) / k, u1 = double(a + 1) / k, w0 = double(b) / k, w1 = double(b + 1) / k;
        if (e.poly.n == 4) {
          auto at = [&](double u, double w) { return (1 - u) * (1 - w) * v[0] + u * (1 - w) * v[1] + u * w * v[2] + (1 - u) * w * v[3]; };
          add({at(u0, w0), at(u1, w0), at(u1, w1), at(u0, w1)});
        } else if (a + b < k) {
          auto at = [&](double u, double w) { return v[0] + u * (v[1] - v[0]) + w * (v[2] - v[0]); };
          add({at(u0, w0), at(u1, w0), at(u0, w1)});
          if (a + b + 1 < k) add({at(u1, w0), at(u1, w1), at(u0, w1)});
        }
      }
  }
  return f;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string t; std::getline(in, t, ',');) out.push_back(t);
  return out;
}

struct Timing {
  double wallMs = 0.0, cpuMs = 0.0, updated = 0.0, maxWallMs = 0.0;
};

Timing timeUpdates(hr::ExtensionDisplay& d, const std::vector<hr::Vec3>& eyes, double threshold) {
  d.update(eyes.front(), 0.0);  // every vertex once, as the viewer's first frame
  Timing t;
  std::clock_t c0 = std::clock();
  auto t0 = std::chrono::steady_clock::now();
  for (std::size_t i = 1; i < eyes.size(); ++i) {
    auto f0 = std::chrono::steady_clock::now();
    t.updated += double(d.update(eyes[i], threshold));
    t.maxWallMs = std::max(t.maxWallMs, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - f0).count());
  }
  const double n = double(eyes.size() - 1);
  t.wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / n;
  t.cpuMs = 1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC / n;
  t.updated /= n;
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene = std::string(GHR_SOURCE_DIR) + "/scenes/three_lights.json";
  std::string walk = std::string(GHR_SOURCE_DIR) + "/scenes/walkthroughs/three_lights.json";
  std::vector<std::string> bases = {"haar", "tetra", "sh8", "sh16"};
  std::vector<std::string> sizes = {"10000", "100000", "1000000"};
  int frames = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string k = argv[i], v = argv[i + 1];
    if (k == "--scene") scene = v;
    else if (k == "--walkthrough") walk = v;
    else if (k == "--basis") bases = split(v);
    else if (k == "--sizes") sizes = split(v);
    else if (k == "--frames") frames = std::stoi(v);
    else {
      std::fprintf(stderr, "unknown option %s\n", k.c_str());
      return 2;
    }
  }
  for (const auto& b : bases)
    if (!kBases.count(b)) {
      std::fprintf(stderr, "--basis: unknown %s (haar, tetra, sh8, sh16)\n", b.c_str());
      return 2;
    }
  view::CameraPath path = view::loadCameraPath(walk);
  const int all = tbb::info::default_concurrency();
  std::printf("scene %s, walkthrough %s (%d frames at %g fps), %d hardware threads\n", scene.c_str(), walk.c_str(),
              path.frameCount(), path.fps, all);
  std::printf("| basis | glossy vertices | threads | threshold deg | frames | ms/frame (wall) | max ms (wall) | ms/frame (CPU) | vertices updated/frame | ns (wall) per vertex update |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  std::map<std::string, double> cost, cpu;  // key: basis|size|threads|threshold -> wall, CPU ms/frame
  for (const std::string& bn : bases) {
    Solved s = solve(scene, kBases.at(bn));
    std::size_t leaves = 0;
    {
      hr::ExtensionDisplay real(s.sol, *s.ext);
      for (std::uint32_t i = 0; i < s.sol.elements.size(); ++i) leaves += real.simulated(i);
      std::fprintf(stderr, "%s: solved in %.1f s, %zu glossy leaves, %zu glossy display vertices in the solution\n", bn.c_str(),
                   s.seconds, leaves, real.vertexCount());
    }
    for (const std::string& sz : sizes) {
      const double target = std::stod(sz);
      int k = std::max(1, int(std::lround(std::sqrt(target / double(std::max<std::size_t>(leaves, 1))))));
      std::vector<std::uint32_t> parent;
      hr::Solution fine = refine(s.sol, *s.ext, k, parent);
      Refined ext(*s.ext, std::move(parent));
      hr::ExtensionDisplay d(fine, ext);
      // Fewer frames for the larger displays keep the run within minutes; always consecutive frames.
      int n = frames > 0 ? frames : target <= 2e4 ? 60 : target <= 2e5 ? 20 : 6;
      n = std::min(n, path.frameCount());
      std::vector<hr::Vec3> eyes;
      for (int i = 0; i < n; ++i) eyes.push_back(view::cameraAt(path, path.frameTime(i), 1, 1).eye);
      if (eyes.size() < 2) eyes.push_back(eyes.front());
      for (int threads : {1, all}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        for (double threshold : {0.0, 2.0}) {
          Timing t = timeUpdates(d, eyes, threshold);
          std::printf("| %s | %zu | %d | %g | %zu | %.3f | %.3f | %.3f | %.0f | %.1f |\n", kBases.at(bn).name.c_str(), d.vertexCount(),
                      threads, threshold, eyes.size() - 1, t.wallMs, t.maxWallMs, threads == 1 ? t.cpuMs : NAN, t.updated,
                      t.updated > 0 ? 1e6 * t.wallMs / t.updated : NAN);
          std::fflush(stdout);
          cost[bn + "|" + sz + "|" + std::to_string(threads) + "|" + std::to_string(threshold > 0)] = t.wallMs;
          cpu[bn + "|" + sz + "|" + std::to_string(threads) + "|" + std::to_string(threshold > 0)] = t.cpuMs;
        }
      }
    }
  }
  // One-thread comparisons in CPU time (robust on a shared machine); threads can only be compared by wall time.
  std::printf("\nratios, same size, side by side in this run (one thread: CPU ms per frame; threads: wall ms per frame):\n");
  auto get = [](const std::map<std::string, double>& m, const std::string& b, const std::string& sz, int th, int thr) {
    auto it = m.find(b + "|" + sz + "|" + std::to_string(th) + "|" + std::to_string(thr));
    return it == m.end() ? NAN : it->second;
  };
  for (const std::string& sz : sizes) {
    std::printf("  %s vertices:", sz.c_str());
    if (cost.count("haar|" + sz + "|1|0") && cost.count("sh16|" + sz + "|1|0"))
      std::printf(" Haar / SH-16 %.2f;", get(cpu, "haar", sz, 1, 0) / get(cpu, "sh16", sz, 1, 0));
    for (const std::string& b : bases)
      std::printf(" %s: threshold 0 / 2 deg %.2f, 1 thread / %d threads %.2f;", b.c_str(), get(cpu, b, sz, 1, 0) / get(cpu, b, sz, 1, 1),
                  all, get(cost, b, sz, 1, 0) / get(cost, b, sz, all, 0));
    std::printf("\n");
  }
  return 0;
}
