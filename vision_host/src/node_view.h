// What an extension sees of the VISION-like host (hr/host_view.h): every element and cluster under
// a NodeId. Elements are numbered between shots, surface by surface and depth first, the children
// of an element consecutively, so a node's children are one contiguous run of ids and the numbering
// does not depend on which thread created which element. Clusters are the cluster tree's indices.
#pragma once
#include <hr/host_view.h>
#include <hr/scene.h>
#include <vision/hierarchy.h>

#include <vector>

namespace vision::detail {

class NodeView final : public hr::HostView {
 public:
  NodeView(const hr::Scene& scene, Hierarchy& h);
  /// Numbers the elements created since the last call; appends the elements that gained children.
  void number(std::vector<Element*>& split);
  static hr::NodeId cluster(std::uint32_t c) { return hr::NodeId{c | hr::NodeId::kClusterBit}; }
  const Element& element(hr::NodeId n) const { return *nodes_[n.index()]; }

  hr::NodeId root() const override { return cluster(0); }
  hr::NodeInfo info(hr::NodeId n) const override;
  std::span<const hr::NodeId> children(hr::NodeId n) const override;
  std::size_t elementCount() const override { return nodes_.size(); }
  std::size_t clusterCount() const override { return h_.clusters().size(); }
  hr::MaterialInfo material(std::uint32_t id) const override;
  std::size_t materialCount() const override { return scene_.materials.size(); }

 private:
  void add(Element& e);
  const hr::Scene& scene_;
  Hierarchy& h_;
  std::vector<Element*> nodes_;                      // per element id
  std::vector<hr::NodeId> ids_;                      // ids_[i] = element i: children are runs of it
  std::vector<std::vector<hr::NodeId>> clusterKids_;  // child clusters, then root elements
};

}  // namespace vision::detail
