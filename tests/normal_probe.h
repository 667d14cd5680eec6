// Shared by the hosts' display-normal tests: an extension that shows the normal the display asks a
// leaf at, and the worst angle between those and a sphere's exact normals over its leaves' corners,
// both ways the display evaluates (a still image's point, the viewer's per-vertex value).
#pragma once
#include <hr/extension.h>
#include <hr/extension_display.h>
#include <hr/solution.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace testutil {

inline double degreesBetween(const hr::Vec3& a, const hr::Vec3& b) {
  return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) * 180.0 / hr::kPi;
}

/// Radiance = the normal a leaf is seen at + (1, 1, 1), on the shiny material only; asked without
/// one, the leaf's own (its polygon's).
class NormalProbe : public hr::Extension {
 public:
  explicit NormalProbe(const hr::Solution& s) : s_(s) {}
  std::string_view name() const override { return "normal-probe"; }
  bool simulates(const hr::MaterialInfo& m) const override { return m.specular.x > 0.0; }
  hr::Rgb radiance(hr::NodeId n, const hr::Vec3&) const override {
    return s_.patches[s_.elements[n.index()].patch].normal + hr::Vec3(1.0);
  }
  hr::Rgb radiance(hr::NodeId, const hr::Vec3&, const hr::Vec3& n) const override { return n + hr::Vec3(1.0); }

 private:
  const hr::Solution& s_;
};

/// A shiny sphere of radius 0.5 at the origin (object 0) over a floor, lit by a small lamp close to
/// one side, so that its leaves are refined unevenly. `settings` is appended as the scene's.
inline std::string shinySphereScene(const std::string& settings) {
  return R"({ "name": "normals",
    "materials": { "shiny": { "diffuse": [0.5, 0.5, 0.5], "specular": [0.3, 0.3, 0.3], "exponent": 200 },
                   "grey": { "diffuse": [0.5, 0.5, 0.5] }, "lamp": { "emission": [50, 50, 50] } },
    "objects": [ { "type": "sphere", "material": "shiny", "center": [0, 0, 0], "radius": 0.5 },
                 { "type": "quad", "material": "grey", "vertices": [[-3,-3,-0.5],[3,-3,-0.5],[3,3,-0.5],[-3,3,-0.5]] },
                 { "type": "quad", "material": "lamp", "vertices": [[0.55,-0.1,0.9],[0.55,0.1,0.9],[0.75,0.1,0.7],[0.75,-0.1,0.7]] } ],
    "settings": )" + settings + " }";
}

/// The largest angle, degrees, between the normal the display shades object 0's leaf corners at and
/// the unit sphere direction of each corner; `corners` counts them.
inline double worstShadingDegrees(const hr::Solution& s, std::size_t& corners) {
  NormalProbe probe(s);
  hr::ExtensionDisplay d(s, probe);
  const hr::Vec3 eye(0.3, -3.0, 2.0);
  d.update(eye);
  double worst = 0.0;
  corners = 0;
  for (std::uint32_t i = 0; i < s.elements.size(); ++i) {
    const hr::SolutionElement& e = s.elements[i];
    if (s.patches[e.patch].object != 0 || !d.simulated(i)) continue;
    for (int k = 0; k < e.poly.n; ++k) {
      const hr::Vec3 v = e.poly.v[std::size_t(k)];
      // A still image shades the sphere's own point its ray meets (CurvedSurface::meet), the viewer
      // the vertex, both at the radial direction there (a sphere about the origin). A still image
      // sees only the side facing the eye: corners on the far side are the viewer's alone.
      const hr::Vec3 toEye = glm::normalize(eye - v);
      const hr::Vec3 seen = s.surfaces.empty() ? v : s.surfaces[0].meet(v, toEye);
      const hr::Vec3 vertex = d.cornerValues()[d.firstCorner(i) + std::uint32_t(k)] - hr::Vec3(1.0);
      worst = std::max(worst, degreesBetween(vertex, v));
      if (glm::dot(v, toEye) > 0.0) worst = std::max(worst, degreesBetween(d.radiance(i, v, toEye) - hr::Vec3(1.0), seen));
      ++corners;
    }
  }
  return worst;
}

}  // namespace testutil
