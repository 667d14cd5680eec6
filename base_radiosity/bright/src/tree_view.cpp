// The BRIGHT-like host's nodes as an extension sees them (tree_view.h).
#include "tree_view.h"

namespace hr::detail {

NodeInfo TreeView::info(NodeId n) const {
  NodeInfo i;
  if (n.isCluster()) {
    const Cluster& c = h_.cluster(n.index());
    i.center = c.center;
    i.area = c.area;
    i.bounds = c.bounds;
    return i;
  }
  const Element& e = h_.element(n.index());
  i.center = e.center;
  i.normal = e.normal;
  // The area light arrives at and leaves from: an element partly under a coplanar cover (a floor
  // element at a box's foot) has its radiosity, and so its reflected power, over its open part.
  i.area = e.area * double(open_[n.index()]);
  i.planar = true;
  i.leaf = e.leaf();
  i.material = h_.patches()[e.patch].material;
  i.object = h_.patches()[e.patch].object;
  for (int k = 0; k < e.poly.n; ++k) i.bounds.grow(e.poly.v[k]);
  return i;
}

MaterialInfo TreeView::material(std::uint32_t id) const {
  const Material& m = scene_.materials[id];
  return {m.diffuse, m.specular, m.exponent, m.emission};
}

}  // namespace hr::detail
