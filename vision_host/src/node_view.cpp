// The extension's view of the VISION-like host's nodes (see node_view.h).
#include "node_view.h"

namespace vision::detail {

NodeView::NodeView(const hr::Scene& scene, Hierarchy& h) : scene_(scene), h_(h) {
  // Root elements first: the id of a surface's root is the surface's index.
  for (Element& r : h.roots()) add(r);
  for (const Cluster& c : h.clusters()) {
    std::vector<hr::NodeId> kids;
    for (std::uint32_t k : c.clusters) kids.push_back(cluster(k));
    for (std::uint32_t k : c.surfaces) kids.push_back(hr::NodeId{h.roots()[k].id});
    clusterKids_.push_back(std::move(kids));
  }
  std::vector<Element*> none;
  number(none);
}

void NodeView::add(Element& e) {
  e.id = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back(&e);
  ids_.push_back(hr::NodeId{e.id});
}

void NodeView::number(std::vector<Element*>& split) {
  auto visit = [&](auto&& self, Element& e) -> void {
    if (e.nkids > 0 && e.kids[0].id == hr::kNone) {
      for (int k = 0; k < e.nkids; ++k) add(e.kids[k]);
      split.push_back(&e);
    }
    for (int k = 0; k < e.nkids; ++k) self(self, e.kids[k]);
  };
  for (Element& r : h_.roots()) visit(visit, r);
}

hr::NodeInfo NodeView::info(hr::NodeId n) const {
  hr::NodeInfo i;
  if (n.isCluster()) {
    if (n.index() >= h_.clusters().size()) return i;
    const Geometry& g = h_.clusters()[n.index()].g;
    i.center = g.center, i.area = g.area, i.bounds = g.box;
    return i;
  }
  if (n.index() >= nodes_.size()) return i;
  const Element& e = *nodes_[n.index()];
  const Surface& s = h_.surfaces()[e.surface];
  i.center = e.g.center;
  // A curved element reports its mean normal: the extension reflects a leaf about one normal, as it
  // does a facet of a tessellation.
  i.normal = s.planar() ? e.g.coneAxis : e.g.normal;
  i.area = e.g.area;
  i.planar = s.planar();
  i.leaf = e.leaf();
  i.material = s.material;
  i.object = s.object;
  i.bounds = e.g.box;
  return i;
}

std::span<const hr::NodeId> NodeView::children(hr::NodeId n) const {
  if (n.isCluster()) return n.index() < clusterKids_.size() ? std::span<const hr::NodeId>(clusterKids_[n.index()]) : std::span<const hr::NodeId>();
  if (n.index() >= nodes_.size()) return {};
  const Element& e = *nodes_[n.index()];
  if (e.nkids == 0 || e.kids[0].id == hr::kNone) return {};
  return std::span<const hr::NodeId>(ids_.data() + e.kids[0].id, e.nkids);
}

hr::MaterialInfo NodeView::material(std::uint32_t id) const {
  const hr::Material& m = scene_.materials[id];
  return {m.diffuse, m.specular, m.exponent, m.emission};
}

}  // namespace vision::detail
