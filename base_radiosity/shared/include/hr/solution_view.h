// The host's view of a saved solution, for an extension that loads its data back (render, inspect,
// the viewer): the elements of the stored quadtrees with their geometry and materials. A saved
// solution keeps no clusters, so clusterCount() is 0 and root() names the first patch's root.
#pragma once
#include <hr/extension.h>
#include <hr/solution.h>

#include <vector>

namespace hr {

class SolutionView final : public HostView {
 public:
  explicit SolutionView(const Solution& s);
  NodeId root() const override { return NodeId{0}; }
  NodeInfo info(NodeId n) const override;
  std::span<const NodeId> children(NodeId n) const override;
  std::size_t elementCount() const override { return s_.elements.size(); }
  std::size_t clusterCount() const override { return 0; }
  MaterialInfo material(std::uint32_t id) const override;
  std::string materialName(std::uint32_t id) const override;
  std::size_t materialCount() const override { return s_.materials.size(); }

 private:
  const Solution& s_;
  std::vector<NodeId> kids_;         // the children of inner elements, 4 each
  std::vector<std::uint32_t> slot_;  // per element: its children in kids_, or kNone for a leaf
};

}  // namespace hr
