// What an extension may read of the host: node ids, a node's geometry and material, the tree, and
// the scene's materials. Read-only and safe to call from many threads at once; valid between the
// host's attach() notices (the node set only grows, ids never change).
#pragma once
#include <hr/types.h>

#include <span>
#include <string>

namespace hr {

/// An element or a cluster. Clusters carry the top bit; the rest is a dense host index.
struct NodeId {
  std::uint32_t value = kNone;
  static constexpr std::uint32_t kClusterBit = 0x80000000u;
  bool isCluster() const { return (value & kClusterBit) != 0; }
  std::uint32_t index() const { return value & ~kClusterBit; }
  friend bool operator==(NodeId a, NodeId b) { return a.value == b.value; }
};

struct NodeInfo {
  Vec3 center{0.0};
  Vec3 normal{0.0};     // unit normal for planar nodes, zero for clusters
  double area = 0.0;    // m^2 (sum over the subtree for clusters)
  bool planar = false;  // an element of a planar patch
  bool leaf = false;
  std::uint32_t material = kNone;  // kNone for clusters
  std::uint32_t object = kNone;
  Aabb bounds;
};

/// Material parameters as an extension needs them (modified Phong; emission in W/(m^2 sr)).
struct MaterialInfo {
  Rgb diffuse{0.0}, specular{0.0};
  double exponent = 1.0;
  Rgb emission{0.0};
};

class HostView {
 public:
  virtual ~HostView() = default;
  virtual NodeId root() const = 0;
  virtual NodeInfo info(NodeId) const = 0;
  virtual std::span<const NodeId> children(NodeId) const = 0;
  virtual std::size_t elementCount() const = 0;
  virtual std::size_t clusterCount() const = 0;
  virtual MaterialInfo material(std::uint32_t id) const = 0;
  virtual std::size_t materialCount() const = 0;
  /// The scene's name of a material, for reports (an extension's choice per material); may be empty.
  virtual std::string materialName(std::uint32_t) const { return {}; }
};

}  // namespace hr
