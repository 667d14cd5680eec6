// Solution snapshot and point location (the smooth display reconstruction: reconstruct.cpp).
#include <hr/solution.h>

#include <cmath>
#include <limits>

namespace hr {

Solution makeSolution(const Scene& scene, const Hierarchy& h, const std::vector<Rgb>& B) {
  Solution s;
  s.sceneName = scene.name;
  s.patches = h.patches();
  s.materials = scene.materials;
  s.cameras = scene.cameras;
  s.objectCount = static_cast<std::uint32_t>(scene.objects.size());
  s.elements.reserve(h.elements().size());
  for (std::size_t i = 0; i < h.elements().size(); ++i) {
    const Element& e = h.element(static_cast<std::uint32_t>(i));
    s.elements.push_back({e.poly, e.patch, e.firstChild, e.level, B[i]});
  }
  reconstruct(s);
  return s;
}

std::uint32_t locateLeaf(const Solution& s, std::uint32_t patch, const Vec3& x) {
  std::uint32_t e = patch;
  const Vec3& n = s.patches[patch].normal;
  while (!s.elements[e].leaf()) {
    std::uint32_t best = s.elements[e].firstChild;
    double bestIn = -std::numeric_limits<double>::infinity();
    for (std::uint32_t k = 0; k < 4; ++k) {
      std::uint32_t c = s.elements[e].firstChild + k;
      double in = s.elements[c].poly.insideness(x, n);
      if (in > bestIn) {
        bestIn = in;
        best = c;
      }
    }
    e = best;
  }
  return e;
}

}  // namespace hr
