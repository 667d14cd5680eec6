// Shared test scaffolding: solve a JSON scene text in memory and expose the results.
#pragma once
#include <hr/output.h>
#include <hr/solution.h>
#include <hr/solver.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

namespace testutil {

/// Unit emitter (L_e = 1 W/(m^2 sr), rho = 0) facing a unit receiver (rho = 0.8) at distance 1.
inline const char* kParallelPlates = R"({
  "materials": { "e": { "emission": [1,1,1] }, "r": { "diffuse": [0.8,0.8,0.8] } },
  "objects": [
    { "type": "quad", "material": "e", "vertices": [[0,0,1],[0,1,1],[1,1,1],[1,0,1]] },
    { "type": "quad", "material": "r", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]] } ] })";

/// A closed unit cube, inward-facing, every face emitting L_e = 1 and reflecting rho: B = pi / (1 - rho).
inline std::string furnace(double rho) {
  const std::string r = std::to_string(rho);
  return R"({ "materials": { "g": { "diffuse": [)" + r + "," + r + "," + r + R"(], "emission": [1,1,1] } },
  "objects": [ { "type": "box", "material": "g", "min": [0,0,0], "max": [1,1,1], "facing": "inward" } ] })";
}

/// A 4 x 4 m floor (rho 0.5) lit by a 10 cm square lamp (L_e = 20) 0.5 m above it, facing down, and
/// nothing else: an open scene whose floor radiance is rho L_e F, F the point-to-polygon form factor
/// (lampOverFloorRadiance). The camera sees the floor obliquely, the lamp's dark back in it.
inline const char* kLampOverFloor = R"({
  "materials": { "floor": { "diffuse": [0.5,0.5,0.5] }, "lamp": { "diffuse": [0,0,0], "emission": [20,20,20] } },
  "objects": [
    { "type": "quad", "material": "floor", "vertices": [[-2,0,-2],[-2,0,2],[2,0,2],[2,0,-2]] },
    { "type": "quad", "material": "lamp", "vertices": [[-0.05,0.5,-0.05],[0.05,0.5,-0.05],[0.05,0.5,0.05],[-0.05,0.5,0.05]] } ],
  "cameras": [ { "name": "top", "eye": [0, 3.2, 2.2], "look_at": [0, 0, 0.3], "up": [0, 1, 0], "fov_y_deg": 60,
                 "width": 160, "height": 120 } ] })";

/// kLampOverFloor's floor radiance at x, W/(m^2 sr), in closed form (Lambert's formula, written out
/// here rather than taken from the core's kernel: F = 1/(2 pi) times the sum over the lamp's edges
/// of the angle each subtends times the cosine between its plane and the floor's normal).
inline double lampOverFloorRadiance(const hr::Vec3& x) {
  const hr::Vec3 lamp[4] = {{-0.05, 0.5, -0.05}, {0.05, 0.5, -0.05}, {0.05, 0.5, 0.05}, {-0.05, 0.5, 0.05}};
  double f = 0.0;
  for (int i = 0; i < 4; ++i) {
    const hr::Vec3 a = glm::normalize(lamp[i] - x), b = glm::normalize(lamp[(i + 1) % 4] - x), c = glm::cross(a, b);
    const double s = glm::length(c);
    if (s > 0.0) f += std::atan2(s, glm::dot(a, b)) * c.y / s;
  }
  return 0.5 * 20.0 * std::abs(f) / (2.0 * hr::kPi);
}

/// Relative RMSE (luminance = any channel: grey) of a solution's image of kLampOverFloor's floor
/// against the closed form, over the floor's pixels: its smooth display or (flat) each leaf's own value.
inline double lampOverFloorError(const hr::Solution& sol, bool flat) {
  const hr::Camera& cam = sol.cameras.at(0);
  const hr::Image img = flat ? hr::render(sol, cam, [&](std::uint32_t leaf, const hr::Vec3&, const hr::Vec3&) {
    return sol.elements[leaf].radiosity / hr::kPi;
  })
                             : hr::render(sol, cam);
  const hr::Image exact = hr::render(sol, cam, [&](std::uint32_t, const hr::Vec3& x, const hr::Vec3&) {
    return hr::Rgb(lampOverFloorRadiance(x));
  });
  double se = 0.0, sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < img.objectId.size(); ++i) {
    if (img.objectId[i] != 0) continue;  // the floor's pixels
    const double d = img.rgb[3 * i] - exact.rgb[3 * i];
    se += d * d, sum += exact.rgb[3 * i], ++n;
  }
  return n > 0 ? std::sqrt(se / n) / (sum / n) : 1e300;
}

struct Solved {
  hr::Scene scene;
  std::unique_ptr<hr::Hierarchy> h;
  std::unique_ptr<hr::Visibility> vis;
  std::unique_ptr<hr::Solver> solver;
  hr::SolveStats stats;

  /// Area-weighted mean radiosity (W/m^2) over the leaves of one scene object.
  hr::Rgb meanRadiosity(std::uint32_t object) const {
    hr::Rgb sum(0.0);
    double a = 0.0;
    for (std::size_t i = 0; i < h->elements().size(); ++i) {
      const auto& e = h->element(static_cast<std::uint32_t>(i));
      if (!e.leaf() || h->patches()[e.patch].object != object) continue;
      // Over the open part: a floor element straddling a box's foot has its radiosity there only.
      const double open = e.area * solver->openFraction()[i];
      sum += open * solver->radiosity()[i];
      a += open;
    }
    return sum / a;
  }
};

/// Solver options with a threshold and a depth, the rest at their defaults.
inline hr::SolverOptions options(double eps, int maxLevel) {
  hr::SolverOptions o;
  o.eps = eps;
  o.maxLevel = maxLevel;
  return o;
}

inline Solved solveText(const std::string& json, hr::SolverOptions opt, hr::Extension* ext = nullptr) {
  Solved s;
  s.scene = hr::parseScene(json, "");
  hr::TessellationReport rep;
  auto patches = hr::buildPatches(s.scene, rep);
  s.h = std::make_unique<hr::Hierarchy>(std::move(patches));
  s.vis = std::make_unique<hr::Visibility>(s.h->patches());
  s.solver = std::make_unique<hr::Solver>(s.scene, *s.h, *s.vis, opt, ext);
  s.stats = s.solver->solve();
  return s;
}

/// Runs the glossyhr binary with the given arguments (stderr folded into the output); returns the
/// exit status as pclose reports it (0 on success).
inline int runCli(const std::string& args, std::string& output) {
  std::string cmd = std::string(GHR_BINARY) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return -1;
  output.clear();
  std::array<char, 512> buf;
  while (fgets(buf.data(), buf.size(), p)) output += buf.data();
  return pclose(p);
}

}  // namespace testutil
