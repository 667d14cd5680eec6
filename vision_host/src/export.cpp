// The VISION-like host's result as an hr::Solution, the form every output reads: each leaf becomes
// small flat polygons, one patch each with one element carrying the leaf's radiosity (a quad or
// triangle leaf is one polygon; a star leaf one per polygon edge it spans; a curved leaf a grid whose
// cells turn at most 7.5 degrees). `render` then needs nothing of this host. A flat display (one
// value per element, as VISION showed its solutions) is recorded in the solution's "display"
// section, which hr::reconstruct honours. Smooth display (the default) takes each leaf's corners
// from smooth.cpp, averaged in the primitive's parameter space, and gives every cell vertex the
// bilinear blend of its leaf's corners at its (u, v); the corners travel in the "display" section.
#include <vision/solver.h>

#include "smooth.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vision {
namespace {

constexpr double kCellTurn = 7.5 * hr::kPi / 180.0;

/// Cells of a leaf's display grid along u (at the star map's vertices too) and v.
void cellBreaks(const Surface& s, const Rect& r, std::vector<double>& us, std::vector<double>& vs) {
  int nu = 1, nv = 1;
  if (!s.straightEdges()) nu = std::max(1, int(std::ceil(2.0 * hr::kPi * r.du() / kCellTurn)));
  if (s.kind == SurfaceKind::Sphere) {
    double span = std::acos(std::clamp(1.0 - 2.0 * r.v1, -1.0, 1.0)) - std::acos(std::clamp(1.0 - 2.0 * r.v0, -1.0, 1.0));
    nv = std::max(1, int(std::ceil(std::abs(span) / kCellTurn)));
  }
  us.clear(), vs.clear();
  for (int i = 0; i <= nu; ++i) us.push_back(r.u0 + r.du() * i / nu);
  for (double b : s.breaks())
    if (b > r.u0 && b < r.u1) us.push_back(b);
  std::sort(us.begin(), us.end());
  for (int j = 0; j <= nv; ++j) vs.push_back(r.v0 + r.dv() * j / nv);
}

class Exporter {
 public:
  Exporter(hr::Solution& sol, const Hierarchy& h, std::vector<std::uint32_t>* cellLeaf) : sol_(sol), h_(h), cellLeaf_(cellLeaf) {}

  /// Per solution element: the leaf (index in the order leaf() was called) and each polygon
  /// vertex's place in the leaf's rectangle, (s, t) in [0, 1]^2.
  struct CellSource {
    std::uint32_t leaf;
    std::array<std::array<double, 2>, 4> st;
  };
  std::vector<CellSource> sources;

  void leaf(const Element& e) {
    const Surface& s = h_.surfaces()[e.surface];
    cellBreaks(s, e.rect, us_, vs_);
    const Rect& r = e.rect;
    for (std::size_t j = 0; j + 1 < vs_.size(); ++j)
      for (std::size_t i = 0; i + 1 < us_.size(); ++i) {
        const double cu[4] = {us_[i], us_[i + 1], us_[i + 1], us_[i]}, cv[4] = {vs_[j], vs_[j], vs_[j + 1], vs_[j + 1]};
        Vec3 c[4];
        std::array<std::array<double, 2>, 4> st;
        for (int k = 0; k < 4; ++k) c[k] = s.point(cu[k], cv[k]), st[k] = {(cu[k] - r.u0) / r.du(), (cv[k] - r.v0) / r.dv()};
        add(c, st, s.normal(0.5 * (us_[i] + us_[i + 1]), 0.5 * (vs_[j] + vs_[j + 1])), s, e.B, e.id);
      }
    ++leaves_;
  }

 private:
  /// One cell as a convex polygon counter-clockwise about the surface's front (collapsed corners
  /// dropped: a pole or a disk's centre makes a triangle).
  void add(const Vec3 (&c)[4], const std::array<std::array<double, 2>, 4>& st, const Vec3& front, const Surface& s,
           const Rgb& B, std::uint32_t leaf) {
    hr::Polygon p;
    p.n = 0;
    CellSource src{leaves_, {}};
    for (int q = 0; q < 4; ++q) {
      const Vec3& v = c[q];
      bool dup = false;
      for (int k = 0; k < p.n; ++k) dup = dup || glm::length(v - p.v[k]) <= 1e-12 * (1.0 + glm::length(v));
      if (!dup) src.st[p.n] = st[q], p.v[p.n++] = v;
    }
    if (p.n < 3) return;
    Vec3 a = p.areaVector();
    double area = glm::length(a);
    if (!(area > 1e-14 * p.radius() * p.radius()) || !(area > 0.0)) return;
    if (glm::dot(a, front) < 0.0) {
      std::reverse(p.v.begin(), p.v.begin() + p.n);
      std::reverse(src.st.begin(), src.st.begin() + p.n);
      a = -a;
    }
    sources.push_back(src);
    hr::Patch pt;
    pt.poly = p;
    pt.normal = a / area;
    pt.area = area;
    pt.material = s.material;
    pt.object = s.object;
    const std::uint32_t id = static_cast<std::uint32_t>(sol_.patches.size());
    sol_.patches.push_back(pt);
    sol_.elements.push_back({p, id, hr::kNone, 0, B});
    if (cellLeaf_) cellLeaf_->push_back(leaf);
  }

  hr::Solution& sol_;
  const Hierarchy& h_;
  std::vector<std::uint32_t>* cellLeaf_;
  std::vector<double> us_, vs_;
  std::uint32_t leaves_ = 0;
};

/// Each leaf hidden (hr::hiddenLeaves, by its cells' area): the no-halo rule of the smoothing.
std::vector<char> hiddenByArea(const hr::Solution& sol, const std::vector<Exporter::CellSource>& src, std::size_t leaves) {
  const std::vector<char> cell = hr::hiddenLeaves(sol);
  std::vector<double> hid(leaves, 0.0), all(leaves, 0.0);
  for (std::size_t i = 0; i < src.size(); ++i) {
    const double a = sol.elements[i].poly.area();
    all[src[i].leaf] += a;
    if (cell[i]) hid[src[i].leaf] += a;
  }
  std::vector<char> out(leaves, 0);
  for (std::size_t l = 0; l < leaves; ++l) out[l] = hid[l] > 0.5 * all[l] ? 1 : 0;
  return out;
}

}  // namespace

hr::Solution makeSolution(const hr::Scene& scene, const Hierarchy& h, Display display, std::vector<std::uint32_t>* cellLeaf) {
  hr::Solution sol;
  sol.sceneName = scene.name;
  sol.host = "vision";
  sol.materials = scene.materials;
  sol.cameras = scene.cameras;
  sol.objectCount = static_cast<std::uint32_t>(scene.objects.size());
  if (cellLeaf) cellLeaf->clear();
  Exporter x(sol, h, cellLeaf);
  std::vector<const Element*> leaves;
  for (const Element& r : h.roots())
    forEachElement(r, [&](const Element& e) {
      if (!e.leaf()) return;
      x.leaf(e);
      leaves.push_back(&e);
    });
  if (display == Display::Flat) {
    hr::setSection(sol, "display", "flat");
  } else {
    const std::vector<LeafCorners> lc = smoothCorners(h, leaves, hiddenByArea(sol, x.sources, leaves.size()));
    std::vector<std::array<Rgb, 4>> corners(sol.elements.size());
    for (std::size_t i = 0; i < corners.size(); ++i) {
      const Exporter::CellSource& src = x.sources[i];
      const LeafCorners& c = lc[src.leaf];
      corners[i].fill(Rgb(0.0));
      for (int k = 0; k < sol.elements[i].poly.n; ++k) {
        const double a = src.st[k][0], b = src.st[k][1];
        corners[i][k] = (1.0 - a) * (1.0 - b) * c[0] + a * (1.0 - b) * c[1] + a * b * c[2] + (1.0 - a) * b * c[3];
      }
    }
    hr::setSection(sol, "display", hr::encodeDisplayCorners(corners));
  }
  // The display shades curved objects at their exact normals (hr/curved_surface.h).
  const std::vector<hr::CurvedSurface> curved = hr::curvedSurfaces(scene);
  if (hr::anyCurved(curved)) hr::setSection(sol, hr::kSurfaces, hr::encodeSurfaces(curved));
  hr::reconstruct(sol);
  return sol;
}

}  // namespace vision
