// A tiny host for the extension's tests: planar elements (leaves and inner elements, quadtree-split
// on demand) under clusters, with materials; element and cluster indices are dense and clusters carry
// the top bit, as hr/host_view.h says. It also plays the host's part of the call sequence where a test
// needs it: the pull over the whole tree, children first.
#pragma once
#include <glossy/illumination_samples.h>

#include <memory>
#include <vector>

namespace testhost {

using hr::NodeId;
using hr::Rgb;
using hr::Vec3;

class FakeHost final : public hr::HostView {
 public:
  struct Node {
    hr::NodeInfo info;
    std::vector<NodeId> children;
  };
  std::vector<Node> elements, clusters;
  std::vector<hr::MaterialInfo> materials;
  NodeId top{};

  NodeId root() const override { return top; }
  hr::NodeInfo info(NodeId id) const override { return node(id).info; }
  std::span<const NodeId> children(NodeId id) const override { return node(id).children; }
  std::size_t elementCount() const override { return elements.size(); }
  std::size_t clusterCount() const override { return clusters.size(); }
  hr::MaterialInfo material(std::uint32_t id) const override { return materials.at(id); }
  std::size_t materialCount() const override { return materials.size(); }

  const Node& node(NodeId id) const { return id.isCluster() ? clusters.at(id.index()) : elements.at(id.index()); }
  Node& node(NodeId id) { return id.isCluster() ? clusters.at(id.index()) : elements.at(id.index()); }

  std::uint32_t addMaterial(const hr::MaterialInfo& m) {
    materials.push_back(m);
    return std::uint32_t(materials.size() - 1);
  }
  NodeId addElement(const Vec3& centre, const Vec3& normal, double area, std::uint32_t material) {
    Node n;
    n.info.center = centre;
    n.info.normal = glm::normalize(normal);
    n.info.area = area;
    n.info.planar = true;
    n.info.leaf = true;
    n.info.material = material;
    n.info.object = 0;
    elements.push_back(n);
    return NodeId{std::uint32_t(elements.size() - 1)};
  }
  NodeId addCluster(std::vector<NodeId> kids) {
    Node n;
    n.info.leaf = false;
    for (NodeId k : kids) n.info.area += node(k).info.area;
    n.children = std::move(kids);
    clusters.push_back(n);
    top = NodeId{std::uint32_t(clusters.size() - 1) | NodeId::kClusterBit};
    return top;
  }
  /// Splits a leaf element into four coplanar children of a quarter of its area.
  std::vector<NodeId> split(NodeId leaf) {
    hr::NodeInfo p = node(leaf).info;
    std::vector<NodeId> kids;
    for (int k = 0; k < 4; ++k) kids.push_back(addElement(p.center, p.normal, 0.25 * p.area, p.material));
    node(leaf).info.leaf = false;
    node(leaf).children = kids;
    return kids;
  }
  /// The host's pull: every inner node whose subtree holds simulated leaves, children first.
  void pullAll(hr::Extension& ext) const { pullFrom(ext, top); }
  /// The pull of one subtree (disjoint subtrees may be pulled concurrently).
  void pullFrom(hr::Extension& ext, NodeId id) const {
    const Node& n = node(id);
    if (n.children.empty()) return;
    for (NodeId c : n.children) pullFrom(ext, c);
    ext.pull(id, n.children);
  }
  /// The view a saved solution gives: the same elements, no clusters.
  FakeHost elementsOnly() const {
    FakeHost h = *this;
    h.clusters.clear();
    h.top = NodeId{0};
    return h;
  }
  /// Every leaf element whose material the extension simulates.
  std::vector<NodeId> simulatedLeaves(const hr::Extension& ext) const {
    std::vector<NodeId> out;
    for (std::uint32_t i = 0; i < elements.size(); ++i)
      if (elements[i].info.leaf && ext.simulates(materials.at(elements[i].info.material))) out.push_back(NodeId{i});
    return out;
  }
};

/// Glossy (coloured lobe, rho_d 0.2, rho_s (0.5, 0.4, 0.3), exponent n) and diffuse materials.
inline hr::MaterialInfo glossyMaterial(double exponent = 100.0) {
  hr::MaterialInfo m;
  m.diffuse = Rgb(0.2);
  m.specular = Rgb(0.5, 0.4, 0.3);
  m.exponent = exponent;
  return m;
}
inline hr::MaterialInfo diffuseMaterial() {
  hr::MaterialInfo m;
  m.diffuse = Rgb(0.6);
  return m;
}

/// The standard little scene: an inner floor element (normal +z, 1 m^2) split into four glossy leaves,
/// a glossy wall leaf (+x, 0.5 m^2), a diffuse leaf (-y) and a tilted glossy leaf, under one cluster.
struct Scene {
  FakeHost host;
  NodeId floor, wall, diffuse, tilted, cluster;
  std::vector<NodeId> floorLeaves;
  explicit Scene(double exponent = 100.0) {
    std::uint32_t g = host.addMaterial(glossyMaterial(exponent)), d = host.addMaterial(diffuseMaterial());
    floor = host.addElement(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, g);
    floorLeaves = host.split(floor);
    wall = host.addElement(Vec3(-1, 0, 0.5), Vec3(1, 0, 0), 0.5, g);
    diffuse = host.addElement(Vec3(0, 1, 0.5), Vec3(0, -1, 0), 0.5, d);
    tilted = host.addElement(Vec3(0.5, 0.5, 0.5), Vec3(-1, -1, 1), 0.3, g);
    cluster = host.addCluster({floor, wall, diffuse, tilted});
  }
};

/// One sample from direction `toSender` with planar irradiance e (W/m^2).
inline hr::IncidentSample sample(const Vec3& toSender, const Rgb& e) { return {glm::normalize(toSender), e}; }

/// A unit direction at angle theta (radians) from n, at azimuth phi about it.
inline Vec3 around(const Vec3& n, double theta, double phi = 0.0) {
  glossy::Vec3 u, v;
  glossy::orthonormalBasis(n, u, v);
  return std::cos(theta) * n + std::sin(theta) * (std::cos(phi) * u + std::sin(phi) * v);
}

inline std::unique_ptr<glossy::IlluminationSamples> configured(const std::vector<hr::OptionValue>& o = {}) {
  auto ext = std::make_unique<glossy::IlluminationSamples>();
  ext->configure(o);
  return ext;
}

}  // namespace testhost
