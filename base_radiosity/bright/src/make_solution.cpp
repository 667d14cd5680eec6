// The BRIGHT-like host's solved quadtree as the host-independent snapshot every output reads: each
// element with its polygon and radiosity, in the hierarchy's order (element i < patches is the root
// of patch i), then the smooth display reconstruction and the curved objects' exact normals.
#include <hr/solver.h>

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
  // The display shades facets of curved objects at the exact normal of the surface they approximate.
  const std::vector<CurvedSurface> curved = curvedSurfaces(scene);
  if (anyCurved(curved)) setSection(s, kSurfaces, encodeSurfaces(curved));
  reconstruct(s);
  return s;
}

}  // namespace hr
