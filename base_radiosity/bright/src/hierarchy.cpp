// Builds the element quadtrees' roots and the cluster tree. Clusters are split at the median of the
// patch centroids along the longest axis (a plain top-down BVH), which keeps sizes balanced and the
// patches of one cluster contiguous in patchOrder so that points can be sampled by area.
#include <hr/hierarchy.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <numeric>

namespace hr {

Hierarchy::Hierarchy(std::vector<Patch> patches, int leafSize) : patches_(std::move(patches)) {
  patchOrder_.resize(patches_.size());
  std::iota(patchOrder_.begin(), patchOrder_.end(), 0u);
  if (!patches_.empty()) build(0, static_cast<std::uint32_t>(patches_.size()), leafSize);
  // Patches are stored in cluster order, so that a cluster's patches (and their root elements) are
  // contiguous in memory: push/pull and cluster intensities walk them with few cache misses.
  std::vector<Patch> ordered;
  ordered.reserve(patches_.size());
  for (std::uint32_t i : patchOrder_) ordered.push_back(patches_[i]);
  patches_ = std::move(ordered);
  std::iota(patchOrder_.begin(), patchOrder_.end(), 0u);
  elements_.reserve(patches_.size() * 4);
  for (std::uint32_t i = 0; i < patches_.size(); ++i) {
    const Patch& p = patches_[i];
    Element e;
    e.poly = p.poly;
    e.normal = p.normal;
    e.center = p.poly.centroid();
    e.area = p.area;
    e.radius = p.poly.radius();
    e.shape = rectangleOfMoments(p.poly.areaMoments(), p.normal, p.poly.v[1] - p.poly.v[0]);
    e.patch = i;
    elements_.push_back(e);
  }
  childSlot_.assign(elements_.size(), kNone);
  areaPrefix_.assign(patchOrder_.size() + 1, 0.0);
  for (std::size_t i = 0; i < patchOrder_.size(); ++i)
    areaPrefix_[i + 1] = areaPrefix_[i] + patches_[patchOrder_[i]].area;
}

std::uint32_t Hierarchy::build(std::uint32_t begin, std::uint32_t end, int leafSize) {
  std::uint32_t id = static_cast<std::uint32_t>(clusters_.size());
  clusters_.emplace_back();
  Aabb box, cbox;
  double area = 0.0;
  for (std::uint32_t i = begin; i < end; ++i) {
    const Patch& p = patches_[patchOrder_[i]];
    for (int k = 0; k < p.poly.n; ++k) box.grow(p.poly.v[k]);
    cbox.grow(p.poly.centroid());
    area += p.area;
  }
  std::vector<NodeId> kids;
  if (end - begin <= static_cast<std::uint32_t>(leafSize)) {
    // Position i in cluster order: the patch's index once patches are reordered (see above).
    for (std::uint32_t i = begin; i < end; ++i) kids.push_back(NodeId{i});
  } else {
    Vec3 ext = cbox.extent();
    int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(patchOrder_.begin() + begin, patchOrder_.begin() + mid, patchOrder_.begin() + end,
                     [&](std::uint32_t a, std::uint32_t b) {
                       double ca = patches_[a].poly.centroid()[axis], cb = patches_[b].poly.centroid()[axis];
                       return ca < cb || (ca == cb && a < b);
                     });
    kids.push_back(NodeId{build(begin, mid, leafSize) | NodeId::kClusterBit});
    kids.push_back(NodeId{build(mid, end, leafSize) | NodeId::kClusterBit});
  }
  Cluster& c = clusters_[id];
  c.bounds = box;
  // The centre is the area centroid, not the box's centre: light leaves a cluster from its surfaces,
  // and the far-field model of a cluster link (intensity over the squared distance between centres)
  // is then off only to second order in the cluster's size. The radius bounds the cluster about it.
  Vec3 centroid(0.0);
  for (std::uint32_t i = begin; i < end; ++i) {
    const Patch& p = patches_[patchOrder_[i]];
    centroid += p.area * p.poly.areaCentroid();
  }
  c.center = area > 0.0 ? centroid / area : box.center();
  c.spread2 = 0.0;
  for (std::uint32_t i = begin; i < end; ++i) {
    const Patch& p = patches_[patchOrder_[i]];
    Vec3 g = p.poly.areaCentroid() - c.center;
    c.spread2 += p.area * (p.poly.spread2() + glm::dot(g, g));
  }
  c.spread2 = area > 0.0 ? c.spread2 / area : 0.0;
  c.radius = 0.0;
  for (int k = 0; k < 8; ++k) {
    Vec3 corner((k & 1) ? box.hi.x : box.lo.x, (k & 2) ? box.hi.y : box.lo.y, (k & 4) ? box.hi.z : box.lo.z);
    c.radius = std::max(c.radius, glm::length(corner - c.center));
  }
  c.area = area;
  c.children = std::move(kids);
  c.patchBegin = begin;
  c.patchEnd = end;
  return id;
}

std::uint32_t Hierarchy::subdivide(std::uint32_t ei) {
  if (!elements_[ei].leaf()) return elements_[ei].firstChild;
  const std::uint32_t first = static_cast<std::uint32_t>(elements_.size());
  subdivideAll(std::span<const std::uint32_t>(&ei, 1));
  return first;
}

void Hierarchy::subdivideAll(std::span<const std::uint32_t> leaves) {
  const std::size_t first = elements_.size(), slot = childIds_.size();
  elements_.resize(first + 4 * leaves.size());
  childIds_.resize(slot + 4 * leaves.size());
  childSlot_.resize(elements_.size(), kNone);
  // Leaf j's children are 4j.. after `first`: every write has its own place.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 256), [&](const auto& r) {
    for (std::size_t j = r.begin(); j != r.end(); ++j) {
      const std::uint32_t ei = leaves[j], c0 = static_cast<std::uint32_t>(first + 4 * j);
      Element& par = elements_[ei];
      assert(par.leaf());
      auto polys = par.poly.subdivide();
      for (std::uint32_t k = 0; k < 4; ++k) {
        Element& e = elements_[c0 + k];
        e.poly = polys[k];
        e.normal = par.normal;
        e.center = polys[k].centroid();
        e.area = polys[k].area();
        e.radius = polys[k].radius();
        e.shape = rectangleOfMoments(polys[k].areaMoments(), par.normal, polys[k].v[1] - polys[k].v[0]);
        e.patch = par.patch;
        e.parent = ei;
        e.level = par.level + 1;
        childIds_[slot + 4 * j + k] = NodeId{c0 + k};
      }
      par.firstChild = c0;
      childSlot_[ei] = static_cast<std::uint32_t>(slot + 4 * j);
    }
  });
}

std::span<const NodeId> Hierarchy::children(NodeId n) const {
  if (n.isCluster()) return clusters_[n.index()].children;
  std::uint32_t s = childSlot_[n.index()];
  if (s == kNone) return {};
  return std::span<const NodeId>(childIds_.data() + s, 4);
}

}  // namespace hr
