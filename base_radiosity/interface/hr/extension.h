// The whole interface an extension sees of the radiosity host (the glossy extension includes this
// and nothing else of base_radiosity). Four hook points: link gather, push/pull, reflection, display.
// Every hook has an empty default, so a run without an extension is the diffuse core alone. Calls are
// per phase, per link or per leaf, never per ray. Extension data lives in the extension's own arrays
// indexed by NodeId (ids are stable: nodes are only ever appended), never in host node types.
#pragma once
#include <hr/types.h>

#include <span>
#include <string_view>

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

/// Material parameters as the extension needs them (modified Phong; radiance in W/(m^2 sr)).
struct MaterialInfo {
  Rgb diffuse{0.0}, specular{0.0};
  double exponent = 1.0;
  Rgb emission{0.0};
};

/// One link's light after visibility: E_perp is the irradiance on a surface facing the sender.
struct Transfer {
  NodeId sender, receiver;
  Vec3 toSender{0.0};       // unit, receiver -> sender
  Rgb normalIrradiance{0.0};  // W/m^2, visibility included
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
};

class Extension {
 public:
  virtual ~Extension() = default;
  virtual std::string_view name() const = 0;
  /// Materials the extension takes over (e.g. glossy ones). Nodes with none keep the diffuse path.
  virtual bool handles(const MaterialInfo&) const { return false; }
  /// After each refinement pass (the node set may have grown): size side tables.
  virtual void attach(const HostView&) {}
  /// Sender side of a link: exitant intensity of a node the extension owns, W/sr.
  virtual bool exitantIntensity(NodeId, const Vec3& /*dir*/, Rgb& /*watts_per_sr*/) const { return false; }
  /// Link gather, once per link per iteration. Return true if the extension took this light (it
  /// then never reaches the host's diffuse irradiance).
  virtual bool gather(const Transfer&) { return false; }
  /// Push/pull phase, after the host's own push/pull of diffuse quantities.
  virtual void pushPull(const HostView&) {}
  /// Reflection at a leaf the extension owns, called during the host's push with the leaf's total
  /// diffuse-path irradiance (W/m^2).
  virtual void reflect(NodeId /*leaf*/, const Rgb& /*irradiance*/) {}
  /// Display: radiance of a leaf toward a viewer (unit direction leaf -> eye), W/(m^2 sr).
  virtual bool displayRadiance(NodeId /*leaf*/, const Vec3& /*toEye*/, Rgb& /*radiance*/) const { return false; }
};

}  // namespace hr
