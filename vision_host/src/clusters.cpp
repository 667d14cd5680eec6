// The cluster tree over whole surfaces: median splits along the longest axis of the centroids' box,
// leaves of at most leafSize surfaces. A cluster's geometry is its children's combined: box, area,
// area centroid and spread, and a cone that holds every child's cone of normals (a wall of many
// coplanar panels keeps a cone of zero width, so bounded radiosity bounds it as tightly as a patch).
#include <vision/hierarchy.h>

#include <algorithm>
#include <cmath>

namespace vision {
namespace {

/// The smallest cone about the area-weighted mean axis that holds every part's cone.
void mergeCones(Geometry& g, const std::vector<const Geometry*>& parts) {
  Vec3 axis(0.0);
  for (const Geometry* p : parts) axis += p->area * p->coneAxis * (p->coneAngle < hr::kPi ? 1.0 : 0.0);
  double len = glm::length(axis);
  bool wide = false;
  for (const Geometry* p : parts) wide = wide || p->coneAngle >= hr::kPi;
  if (wide || !(len > 1e-9 * g.area)) {
    g.coneAxis = Vec3(0, 0, 1), g.coneAngle = hr::kPi;
    return;
  }
  g.coneAxis = axis / len;
  double a = 0.0;
  for (const Geometry* p : parts)
    a = std::max(a, std::acos(std::clamp(glm::dot(g.coneAxis, p->coneAxis), -1.0, 1.0)) + p->coneAngle);
  g.coneAngle = std::min(a, hr::kPi);
}

}  // namespace

Hierarchy::Hierarchy(std::vector<Surface> surfaces, int leafSize) : surfaces_(std::move(surfaces)) {
  roots_.resize(surfaces_.size());
  for (std::uint32_t i = 0; i < surfaces_.size(); ++i) {
    roots_[i].surface = i;
    roots_[i].g = measure(surfaces_[i], roots_[i].rect);
  }
  if (surfaces_.empty()) return;
  std::vector<std::uint32_t> idx(surfaces_.size());
  for (std::uint32_t i = 0; i < idx.size(); ++i) idx[i] = i;
  build(idx, 0, idx.size(), leafSize);
}

std::uint32_t Hierarchy::build(std::vector<std::uint32_t>& idx, std::size_t begin, std::size_t end, int leafSize) {
  const std::uint32_t me = static_cast<std::uint32_t>(clusters_.size());
  clusters_.emplace_back();
  std::vector<const Geometry*> parts;
  if (end - begin <= std::size_t(leafSize)) {
    for (std::size_t i = begin; i < end; ++i) {
      clusters_[me].surfaces.push_back(idx[i]);
      parts.push_back(&roots_[idx[i]].g);
    }
  } else {
    hr::Aabb cb;
    for (std::size_t i = begin; i < end; ++i) cb.grow(roots_[idx[i]].g.center);
    Vec3 ext = cb.extent();
    int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : ext.y >= ext.z ? 1 : 2;
    std::size_t mid = begin + (end - begin) / 2;
    // Ties broken by index: the tree does not depend on the sort's whims.
    std::nth_element(idx.begin() + std::ptrdiff_t(begin), idx.begin() + std::ptrdiff_t(mid), idx.begin() + std::ptrdiff_t(end),
                     [&](std::uint32_t a, std::uint32_t b) {
                       double ca = roots_[a].g.center[axis], cb2 = roots_[b].g.center[axis];
                       return ca < cb2 || (ca == cb2 && a < b);
                     });
    std::uint32_t l = build(idx, begin, mid, leafSize), r = build(idx, mid, end, leafSize);
    clusters_[me].clusters = {l, r};
    parts = {&clusters_[l].g, &clusters_[r].g};
  }
  Cluster& c = clusters_[me];
  c.surfaceCount = static_cast<std::uint32_t>(end - begin);
  Geometry& g = c.g;
  for (const Geometry* p : parts) {
    g.box.grow(p->box);
    g.area += p->area;
    g.center += p->area * p->center;
  }
  g.center = g.area > 0.0 ? g.center / g.area : g.box.center();
  for (const Geometry* p : parts) {
    Vec3 d = p->center - g.center;
    g.spread2 += p->area * (p->spread2 + glm::dot(d, d));
    g.radius = std::max(g.radius, glm::length(d) + p->radius);
  }
  g.spread2 = g.area > 0.0 ? g.spread2 / g.area : 0.0;
  mergeCones(g, parts);
  return me;
}

}  // namespace vision
