// Shared test scaffolding: solve a JSON scene text in memory and expose the results.
#pragma once
#include <hr/output.h>
#include <hr/solver.h>

#include <array>
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
