// The VISION-like host's nodes. Every surface is the root of a tree of elements: rectangles of its
// parameter square split 1 -> 4, or 1 -> 2 across the longer side when one side is more than twice
// the other. A binary cluster tree is built over the surfaces. Bounded radiosity needs only simple
// geometry per node: a bounding box and a cone of normals (plus area, centroid and spread for the
// far-field estimate), so curved elements and clusters are handled alike.
//
// The element tree is a pointer tree: during a shot each receiver is owned by one task, which alone
// may split it; senders read only `sendKids`, the children that existed when the shot began (set
// between shots), so no task ever reads a child another task is creating.
#pragma once
#include <hr/extension.h>
#include <vision/surface.h>

#include <memory>
#include <vector>

namespace vision {

using hr::Rgb;

/// What bounded radiosity and the far-field estimate need to know of a node.
struct Geometry {
  Vec3 center{0.0};        // area centroid
  Vec3 normal{0.0};        // unit mean normal (zero when the normals cancel, e.g. a whole sphere)
  double area = 0.0;       // m^2
  double radius = 0.0;     // largest distance of a surface point from the centroid, m
  double spread2 = 0.0;    // mean squared distance of the surface from the centroid, m^2
  hr::Aabb box;            // conservative (curvature margin included)
  Vec3 coneAxis{0.0, 0.0, 1.0};
  double coneAngle = 0.0;  // half-angle of the cone of normals, radians; pi: any direction
  hr::SenderRectangle shape;  // a flat element's, as hr::IncidentSample::senderShape (else none)
};

/// Geometry of a parameter rectangle of a surface: quadrature for area, centroid and spread, a grid
/// with a curvature margin for the box and the cone.
Geometry measure(const Surface& s, const Rect& r);

/// How an element splits: up to four child rectangles (1 -> 4, or 1 -> 2 across the longer side).
struct Split {
  Rect kids[4];
  int count = 0;
  int levelStep = 0;  // 2 for 1 -> 4, 1 for 1 -> 2: levels count quarterings
};
Split splitOf(const Surface& s, const Rect& r);

struct Element {
  Rect rect;
  std::uint32_t surface = 0;
  std::uint16_t level = 0;        // in halvings of the area (a 1 -> 4 split adds 2)
  std::uint8_t nkids = 0;         // children (owned by the receiver task during a shot)
  std::uint8_t sendKids = 0;      // children a sender may use this shot
  Geometry g;
  std::unique_ptr<Element[]> kids;
  Rgb B{0.0};     // radiosity, W/m^2 (inner elements: area mean)
  Rgb U{0.0};     // unshot radiosity, W/m^2 (inner: area mean)
  Rgb P{0.0};     // unshot power of the subtree, A U summed, W
  Rgb E{0.0};     // irradiance received this shot at this node (mean over it), W/m^2
  Rgb Etot{0.0};  // all irradiance a leaf has received, W/m^2 (the energy audit's absorption)
  std::uint32_t id = hr::kNone;   // dense index, assigned between shots (the extension's NodeId)
  // An extension's share: what each interaction brought this shot, on the element's surface (only
  // for surfaces the extension simulates; emptied by the push).
  std::vector<hr::IncidentSample> arrivals;
  bool leaf() const { return nkids == 0; }
};

/// A node of the cluster tree: child clusters and surfaces (root elements).
struct Cluster {
  Geometry g;
  std::vector<std::uint32_t> clusters, surfaces;
  Rgb P{0.0};                       // unshot power inside, W
  std::uint32_t table = hr::kNone;  // slot of its unshot intensity table, if it has one
  std::uint32_t surfaceCount = 0;
};

/// Unshot light arriving at a cluster: E_perp toward a sender (on a surface facing it), W/m^2.
struct ClusterSample {
  Vec3 toSender{0.0};
  Rgb Eperp{0.0};
  double distance = 0.0;  // to the sender's centre from the cluster's, m
  double radius = 0.0;    // the sender's, as hr::IncidentSample::radius
  glm::vec3 senderNormal{0.0f};  // as hr::IncidentSample::senderNormal
  hr::SenderRectangle senderShape;  // as hr::IncidentSample::senderShape
};

class Hierarchy {
 public:
  explicit Hierarchy(std::vector<Surface> surfaces, int leafSize = 4);
  const std::vector<Surface>& surfaces() const { return surfaces_; }
  std::vector<Element>& roots() { return roots_; }
  const std::vector<Element>& roots() const { return roots_; }
  std::vector<Cluster>& clusters() { return clusters_; }
  const std::vector<Cluster>& clusters() const { return clusters_; }
  const Surface& surface(const Element& e) const { return surfaces_[e.surface]; }
  /// Creates the children of a leaf (called by the task that owns it).
  void subdivide(Element& e) const;
  hr::Aabb bounds() const { return clusters_.empty() ? hr::Aabb{} : clusters_[0].g.box; }
  double totalArea() const { return clusters_.empty() ? 0.0 : clusters_[0].g.area; }

 private:
  std::uint32_t build(std::vector<std::uint32_t>& idx, std::size_t begin, std::size_t end, int leafSize);
  std::vector<Surface> surfaces_;
  std::vector<Element> roots_;
  std::vector<Cluster> clusters_;
};

/// Visits every element of a surface tree, parents before children.
template <class F>
void forEachElement(Element& e, F&& f) {
  f(e);
  for (int k = 0; k < e.nkids; ++k) forEachElement(e.kids[k], f);
}
template <class F>
void forEachElement(const Element& e, F&& f) {
  f(e);
  for (int k = 0; k < e.nkids; ++k) forEachElement(static_cast<const Element&>(e.kids[k]), f);
}

}  // namespace vision
