// HostView over a saved solution (see solution_view.h).
#include <hr/solution_view.h>

namespace hr {

SolutionView::SolutionView(const Solution& s) : s_(s), slot_(s.elements.size(), kNone) {
  for (std::uint32_t i = 0; i < s.elements.size(); ++i) {
    if (s.elements[i].leaf()) continue;
    slot_[i] = static_cast<std::uint32_t>(kids_.size());
    for (std::uint32_t k = 0; k < 4; ++k) kids_.push_back(NodeId{s.elements[i].firstChild + k});
  }
}

NodeInfo SolutionView::info(NodeId n) const {
  NodeInfo i;
  if (n.isCluster() || n.index() >= s_.elements.size()) return i;
  const SolutionElement& e = s_.elements[n.index()];
  const Patch& p = s_.patches[e.patch];
  i.center = e.poly.centroid();
  i.normal = p.normal;
  i.area = e.poly.area();
  i.planar = true;
  i.leaf = e.leaf();
  i.material = p.material;
  i.object = p.object;
  for (int k = 0; k < e.poly.n; ++k) i.bounds.grow(e.poly.v[k]);
  return i;
}

std::span<const NodeId> SolutionView::children(NodeId n) const {
  if (n.isCluster() || n.index() >= slot_.size() || slot_[n.index()] == kNone) return {};
  return std::span<const NodeId>(kids_.data() + slot_[n.index()], 4);
}

std::string SolutionView::materialName(std::uint32_t id) const { return s_.materials[id].name; }

MaterialInfo SolutionView::material(std::uint32_t id) const {
  const Material& m = s_.materials[id];
  return {m.diffuse, m.specular, m.exponent, m.emission};
}

}  // namespace hr
