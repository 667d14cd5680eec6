// Building the viewer's two lists (see display_lists.h).
#include "display_lists.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <unordered_set>

namespace view {

namespace {

void addVertex(DisplayList& l, const hr::Vec3& p, const hr::Rgb& diffuse, std::array<std::uint32_t, 4> corners, bool glossy,
               float t = 0.0f) {
  for (int k = 0; k < 3; ++k) l.points.push_back(static_cast<float>(p[k]));
  for (int k = 0; k < 3; ++k) l.diffuse.push_back(static_cast<float>(diffuse[k]));
  if (glossy) l.corners.insert(l.corners.end(), corners.begin(), corners.end()), l.edgeT.push_back(t);
}

/// Triangle (a, b, c) wound counter-clockwise around the patch normal n.
void addTriangle(DisplayList& l, const float* pts, std::uint32_t a, std::uint32_t b, std::uint32_t c, const hr::Vec3& n,
                 std::uint32_t leaf) {
  auto at = [&](std::uint32_t i) { return hr::Vec3(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]); };
  if (glm::dot(glm::cross(at(b) - at(a), at(c) - at(a)), n) < 0.0) std::swap(b, c);
  l.triangles.insert(l.triangles.end(), {a, b, c});
  l.triangleLeaf.push_back(leaf);
}

/// Leaf corners by position, to 1e-7 m: subdivision makes a neighbour's corner on an edge that
/// edge's dyadic midpoint, computed alike on both sides. Any patch's: a tessellated surface's patches
/// meet along edges too (a corner of another surface touching the edge only adds a vertex there).
struct CornerKey {
  long long x, y, z;
  bool operator==(const CornerKey&) const = default;
};
struct CornerHash {
  std::size_t operator()(const CornerKey& k) const {
    std::size_t h = 0;
    for (long long v : {k.x, k.y, k.z}) h = h * 1000003u ^ std::hash<long long>()(v);
    return h;
  }
};
CornerKey keyOf(const hr::Vec3& p) { return {std::llround(p.x * 1e7), std::llround(p.y * 1e7), std::llround(p.z * 1e7)}; }

/// The parameters in (0, 1) along edge a -> b at which other leaves have corners, in order: the
/// edge's midpoint if it is one, then recursively in each half.
void edgePoints(const std::unordered_set<CornerKey, CornerHash>& corners, const hr::Vec3& a, const hr::Vec3& b, double t0,
                double t1, int depth, std::vector<double>& out) {
  if (depth > 24) return;
  const hr::Vec3 m = 0.5 * (a + b);
  if (!corners.count(keyOf(m))) return;
  const double tm = 0.5 * (t0 + t1);
  edgePoints(corners, a, m, t0, tm, depth + 1, out);
  out.push_back(tm);
  edgePoints(corners, m, b, tm, t1, depth + 1, out);
}

}  // namespace

DisplayLists buildDisplayLists(const hr::Solution& s, const hr::ExtensionDisplay* display) {
  DisplayLists out;
  std::unordered_set<CornerKey, CornerHash> corners;
  for (const hr::SolutionElement& e : s.elements)
    if (e.leaf())
      for (int k = 0; k < e.poly.n; ++k) corners.insert(keyOf(e.poly.v[k]));
  std::vector<double> ts;
  for (std::uint32_t i = 0; i < s.elements.size(); ++i) {
    const hr::SolutionElement& e = s.elements[i];
    if (!e.leaf()) continue;
    const bool glossy = display && display->simulated(i);
    DisplayList& l = glossy ? out.glossy : out.diffuse;
    const hr::Vec3& n = s.patches[e.patch].normal;
    const std::uint32_t first = static_cast<std::uint32_t>(l.vertexCount());
    const std::uint32_t c0 = glossy ? display->firstCorner(i) : hr::kNone;
    const auto& B = s.cornerRadiosity[i];
    // The boundary: each corner, then the points finer neighbours put on the edge after it.
    std::uint32_t count = 0;
    for (int k = 0; k < e.poly.n; ++k) {
      const int k1 = (k + 1) % e.poly.n;
      addVertex(l, e.poly.v[k], B[k] / hr::kPi, {c0 + std::uint32_t(k), hr::kNone, hr::kNone, hr::kNone}, glossy);
      ++count;
      ts.clear();
      edgePoints(corners, e.poly.v[k], e.poly.v[k1], 0.0, 1.0, 0, ts);
      for (double t : ts) {
        // On the edge, both of the leaf's triangles that touch it interpolate its two corners linearly.
        addVertex(l, (1.0 - t) * e.poly.v[k] + t * e.poly.v[k1], ((1.0 - t) * B[k] + t * B[k1]) / hr::kPi,
                  {c0 + std::uint32_t(k), c0 + std::uint32_t(k1), hr::kNone, hr::kNone}, glossy, static_cast<float>(t));
        ++count;
      }
    }
    if (e.poly.n == 3 && count == 3) {
      addTriangle(l, l.points.data(), first, first + 1, first + 2, n, i);
      continue;
    }
    // The centre carries the mean of the corners, as interpolateCorners() gives it for a quad (and
    // as a triangle's linear interpolation has it at its centroid); the fan around it reproduces
    // that interpolation exactly, the edge points lying on its triangles' outer edges.
    hr::Rgb mean(0.0);
    for (int k = 0; k < e.poly.n; ++k) mean += B[k];
    mean /= double(e.poly.n);
    addVertex(l, e.poly.centroid(), mean / hr::kPi, {c0, c0 + 1, c0 + 2, e.poly.n == 4 ? c0 + 3 : hr::kNone}, glossy);
    const std::uint32_t centre = first + count;
    for (std::uint32_t k = 0; k < count; ++k) addTriangle(l, l.points.data(), first + k, first + (k + 1) % count, centre, n, i);
  }
  return out;
}

void glossyRadiance(const DisplayList& glossy, const hr::ExtensionDisplay& display, float* out) {
  const std::vector<hr::Rgb>& cv = display.cornerValues();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, glossy.vertexCount(), 4096), [&](const auto& r) {
    for (std::size_t v = r.begin(); v != r.end(); ++v) {
      const std::uint32_t* c = &glossy.corners[4 * v];
      hr::Rgb L;
      if (c[1] == hr::kNone) {
        L = cv[c[0]];
      } else if (c[2] == hr::kNone) {
        const double t = glossy.edgeT[v];
        L = (1.0 - t) * cv[c[0]] + t * cv[c[1]];
      } else if (c[3] == hr::kNone) {
        L = (cv[c[0]] + cv[c[1]] + cv[c[2]]) / 3.0;
      } else {
        L = 0.25 * (cv[c[0]] + cv[c[1]] + cv[c[2]] + cv[c[3]]);
      }
      for (int k = 0; k < 3; ++k) out[3 * v + k] = static_cast<float>(L[k]);
    }
  });
}

}  // namespace view
