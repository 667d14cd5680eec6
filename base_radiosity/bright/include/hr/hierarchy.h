// The host's node hierarchy: a quadtree of elements under every root patch, and a binary cluster
// tree over the patches with a single root cluster. Nodes are append-only so NodeIds stay valid.
#pragma once
#include <hr/extension.h>
#include <hr/geometry.h>

#include <vector>

namespace hr {

struct Element {
  Polygon poly;
  Vec3 normal{0.0};
  Vec3 center{0.0};
  double area = 0.0;
  double radius = 0.0;
  SenderRectangle shape;  // as a sender: its rectangle of second moments (IncidentSample::senderShape)
  std::uint32_t patch = 0;
  std::uint32_t parent = kNone;
  std::uint32_t firstChild = kNone;  // four contiguous children, or kNone for a leaf
  std::uint32_t level = 0;
  bool leaf() const { return firstChild == kNone; }
};

struct Cluster {
  Aabb bounds;
  Vec3 center{0.0};
  double radius = 0.0;   // bounding-sphere radius about center
  double spread2 = 0.0;  // area-weighted mean squared distance of its surfaces from center, m^2
  double area = 0.0;     // total surface area inside, m^2
  std::vector<NodeId> children;  // clusters or root elements
  std::uint32_t patchBegin = 0, patchEnd = 0;  // range in Hierarchy::patchOrder
};

class Hierarchy {
 public:
  /// Builds root elements and the cluster tree (leaf clusters hold at most leafSize patches).
  Hierarchy(std::vector<Patch> patches, int leafSize = 4);

  const std::vector<Patch>& patches() const { return patches_; }
  const std::vector<Element>& elements() const { return elements_; }
  const std::vector<Cluster>& clusters() const { return clusters_; }
  const Element& element(std::uint32_t i) const { return elements_[i]; }
  const Cluster& cluster(std::uint32_t i) const { return clusters_[i]; }
  NodeId root() const { return NodeId{0 | NodeId::kClusterBit}; }
  /// Root element of patch p has index p.
  std::uint32_t patchRoot(std::uint32_t p) const { return p; }
  /// Patches in cluster order; a cluster covers [patchBegin, patchEnd). Cumulative areas for sampling.
  const std::vector<std::uint32_t>& patchOrder() const { return patchOrder_; }
  const std::vector<double>& patchAreaPrefix() const { return areaPrefix_; }
  Aabb bounds() const { return clusters_.empty() ? Aabb{} : clusters_[0].bounds; }

  /// Creates the four children of a leaf element; returns the first child's index.
  std::uint32_t subdivide(std::uint32_t element);
  /// Subdivides distinct leaves: the same ids as subdivide() on each in turn, the children's
  /// geometry computed in parallel (refinement splits thousands of leaves at once).
  void subdivideAll(std::span<const std::uint32_t> leaves);
  std::span<const NodeId> children(NodeId n) const;

  double radius(NodeId n) const {
    return n.isCluster() ? clusters_[n.index()].radius : elements_[n.index()].radius;
  }
  double area(NodeId n) const { return n.isCluster() ? clusters_[n.index()].area : elements_[n.index()].area; }
  /// Mean squared distance of a node's surface points from its centre, m^2.
  double spread2(NodeId n) const {
    return n.isCluster() ? clusters_[n.index()].spread2 : elements_[n.index()].poly.spread2();
  }
  Vec3 center(NodeId n) const {
    return n.isCluster() ? clusters_[n.index()].center : elements_[n.index()].center;
  }

 private:
  std::uint32_t build(std::uint32_t begin, std::uint32_t end, int leafSize);
  std::vector<Patch> patches_;
  std::vector<Element> elements_;
  std::vector<Cluster> clusters_;
  std::vector<std::uint32_t> patchOrder_;
  std::vector<double> areaPrefix_;  // areaPrefix_[i] = area of patchOrder_[0..i)
  std::vector<NodeId> childIds_;    // element children as NodeIds, 4 per subdivided element
  std::vector<std::uint32_t> childSlot_;  // element -> offset into childIds_
};

}  // namespace hr
