// Test scaffolding for the VISION-like host: solve a scene in memory, read its leaves.
#pragma once
#include <hr/scene.h>
#include <vision/solver.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace visiontest {

struct Solved {
  hr::Scene scene;
  std::unique_ptr<vision::Hierarchy> h;
  std::unique_ptr<vision::CurvedVisibility> vis;
  std::unique_ptr<vision::Solver> solver;  // an extension's view of the nodes lives in it
  hr::SolveStats stats;

  /// Every leaf of every surface, surfaces in order, each tree depth first.
  std::vector<const vision::Element*> leaves() const {
    std::vector<const vision::Element*> out;
    for (const vision::Element& r : h->roots())
      vision::forEachElement(r, [&](const vision::Element& e) {
        if (e.leaf()) out.push_back(&e);
      });
    return out;
  }
  /// Area-weighted mean radiosity (W/m^2) over the leaves of one scene object.
  hr::Rgb meanRadiosity(std::uint32_t object) const {
    hr::Rgb sum(0.0);
    double a = 0.0;
    for (const vision::Element* e : leaves())
      if (h->surfaces()[e->surface].object == object) sum += e->g.area * e->B, a += e->g.area;
    return a > 0.0 ? sum / a : hr::Rgb(0.0);
  }
};

inline Solved solve(hr::Scene scene, const hr::SolverOptions& opt, hr::Extension* ext = nullptr) {
  Solved s;
  s.scene = std::move(scene);
  vision::SurfaceReport rep;
  s.h = std::make_unique<vision::Hierarchy>(vision::buildSurfaces(s.scene, rep));
  s.vis = std::make_unique<vision::CurvedVisibility>(s.h->surfaces());
  s.solver = std::make_unique<vision::Solver>(s.scene, *s.h, *s.vis, opt, ext);
  s.stats = s.solver->solve();
  return s;
}

inline Solved solveText(const std::string& json, const hr::SolverOptions& opt, hr::Extension* ext = nullptr) {
  return solve(hr::parseScene(json, ""), opt, ext);
}

/// A material block of grey materials: "e" emits L_e = 1 and reflects rho_e, "r" reflects rho_r.
inline std::string greyMaterials(double rhoE, double rhoR) {
  // snprintf, not operator+ chains: GCC 12 warns falsely (-Wrestrict) on "[" + std::string.
  char buf[256];
  std::snprintf(buf, sizeof buf,
                R"("materials": { "e": { "emission": [1,1,1], "diffuse": [%.17g,%.17g,%.17g] }, "r": { "diffuse": [%.17g,%.17g,%.17g] } })",
                rhoE, rhoE, rhoE, rhoR, rhoR, rhoR);
  return buf;
}

}  // namespace visiontest
