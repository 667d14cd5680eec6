// What an extension sees of the BRIGHT-like host (hr/host_view.h): the cluster tree and the element
// quadtrees under NodeIds (a cluster's id has NodeId::kClusterBit, an element's is its index in the
// hierarchy), and the scene's materials. Apart from the solver so that solver.cpp reads as the
// algorithm alone; the VISION-like host's counterpart is vision_host/src/node_view.h.
#pragma once
#include <hr/hierarchy.h>
#include <hr/host_view.h>
#include <hr/scene.h>

namespace hr::detail {

class TreeView final : public HostView {
 public:
  /// open: per element, the fraction of its area no coplanar patch covers (SolverState::open).
  TreeView(const Scene& scene, const Hierarchy& h, const std::vector<float>& open) : scene_(scene), h_(h), open_(open) {}
  NodeId root() const override { return h_.root(); }
  NodeInfo info(NodeId n) const override;
  std::span<const NodeId> children(NodeId n) const override { return h_.children(n); }
  std::size_t elementCount() const override { return h_.elements().size(); }
  std::size_t clusterCount() const override { return h_.clusters().size(); }
  std::size_t materialCount() const override { return scene_.materials.size(); }
  std::string materialName(std::uint32_t id) const override { return scene_.materials[id].name; }
  MaterialInfo material(std::uint32_t id) const override;

 private:
  const Scene& scene_;
  const Hierarchy& h_;
  const std::vector<float>& open_;
};

}  // namespace hr::detail
