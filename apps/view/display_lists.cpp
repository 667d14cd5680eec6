// Building the viewer's two lists (see display_lists.h).
#include "display_lists.h"

#include <tbb/parallel_for.h>

namespace view {

namespace {

void addVertex(DisplayList& l, const hr::Vec3& p, const hr::Rgb& diffuse, std::array<std::uint32_t, 4> corners, bool glossy) {
  for (int k = 0; k < 3; ++k) l.points.push_back(static_cast<float>(p[k]));
  for (int k = 0; k < 3; ++k) l.diffuse.push_back(static_cast<float>(diffuse[k]));
  if (glossy) l.corners.insert(l.corners.end(), corners.begin(), corners.end());
}

/// Triangle (a, b, c) wound counter-clockwise around the patch normal n.
void addTriangle(DisplayList& l, const float* pts, std::uint32_t a, std::uint32_t b, std::uint32_t c, const hr::Vec3& n,
                 std::uint32_t leaf) {
  auto at = [&](std::uint32_t i) { return hr::Vec3(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]); };
  if (glm::dot(glm::cross(at(b) - at(a), at(c) - at(a)), n) < 0.0) std::swap(b, c);
  l.triangles.insert(l.triangles.end(), {a, b, c});
  l.triangleLeaf.push_back(leaf);
}

}  // namespace

DisplayLists buildDisplayLists(const hr::Solution& s, const hr::ExtensionDisplay* display) {
  DisplayLists out;
  for (std::uint32_t i = 0; i < s.elements.size(); ++i) {
    const hr::SolutionElement& e = s.elements[i];
    if (!e.leaf()) continue;
    const bool glossy = display && display->simulated(i);
    DisplayList& l = glossy ? out.glossy : out.diffuse;
    const hr::Vec3& n = s.patches[e.patch].normal;
    const std::uint32_t first = static_cast<std::uint32_t>(l.vertexCount());
    const std::uint32_t c0 = glossy ? display->firstCorner(i) : hr::kNone;
    const auto& B = s.cornerRadiosity[i];
    for (int k = 0; k < e.poly.n; ++k)
      addVertex(l, e.poly.v[k], B[k] / hr::kPi, {c0 + std::uint32_t(k), hr::kNone, hr::kNone, hr::kNone}, glossy);
    if (e.poly.n == 3) {
      addTriangle(l, l.points.data(), first, first + 1, first + 2, n, i);
      continue;
    }
    // The centre carries the mean of the corners, as interpolateCorners() gives it.
    addVertex(l, e.poly.centroid(), 0.25 * (B[0] + B[1] + B[2] + B[3]) / hr::kPi, {c0, c0 + 1, c0 + 2, c0 + 3}, glossy);
    for (std::uint32_t k = 0; k < 4; ++k) addTriangle(l, l.points.data(), first + k, first + (k + 1) % 4, first + 4, n, i);
  }
  return out;
}

void glossyRadiance(const DisplayList& glossy, const hr::ExtensionDisplay& display, float* out) {
  const std::vector<hr::Rgb>& cv = display.cornerValues();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, glossy.vertexCount(), 4096), [&](const auto& r) {
    for (std::size_t v = r.begin(); v != r.end(); ++v) {
      const std::uint32_t* c = &glossy.corners[4 * v];
      hr::Rgb L = c[1] == hr::kNone ? cv[c[0]] : 0.25 * (cv[c[0]] + cv[c[1]] + cv[c[2]] + cv[c[3]]);
      for (int k = 0; k < 3; ++k) out[3 * v + k] = static_cast<float>(L[k]);
    }
  });
}

}  // namespace view
