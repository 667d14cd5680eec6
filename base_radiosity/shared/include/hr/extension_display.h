// The extension's share of a saved solution's display, smooth across elements (paper §5.2): the
// corners of the leaves an extension simulates meet in display vertices (one per position, object and
// material: never blended across objects, materials or creases), each vertex's adjacent leaves are
// evaluated toward the eye, and a leaf corner takes the area-weighted mean of those within 30 degrees
// of its own normal. Still images and the viewer use the same values, so they agree. The viewer
// re-evaluates a vertex only when its view direction turned by more than a threshold since its last
// evaluation (§5.2's quality/update-rate trade-off); a threshold of 0 re-evaluates every vertex.
// Where the leaves meeting at a vertex all lie within 30 degrees of each other but not in one plane
// (a curved or tessellated surface), the vertex has a shading normal and the extension evaluates its
// leaves as seen at that normal: a glossy highlight moves with the surface, not with the leaf.
// Still images go further on such leaves and evaluate every pixel at its interpolated normal. On
// objects whose curved surface the solution carries (Solution::surfaces) vertices and pixels are
// shaded at that surface's exact normal instead of the estimate.
#pragma once
#include <hr/extension.h>
#include <hr/solution.h>

#include <array>
#include <vector>

namespace hr {

class ExtensionDisplay {
 public:
  ExtensionDisplay(const Solution& s, const Extension& ext);
  /// Re-evaluates every display vertex toward the eye point (parallel over vertices).
  void update(const Vec3& eye) { update(eye, 0.0); }
  /// Re-evaluates the display vertices whose direction to the eye turned by more than thresholdDeg
  /// (degrees) since their last evaluation, and every vertex on the first call or with a threshold
  /// of 0; then the corners of those vertices. Returns how many vertices were re-evaluated.
  std::size_t update(const Vec3& eye, double thresholdDeg);
  /// The extension's radiance at x on a leaf, W/(m^2 sr): its corners' values interpolated. Zero
  /// for leaves the extension does not simulate.
  Rgb radiance(std::uint32_t leaf, const Vec3& x) const;
  /// The same seen toward unit toEye from x: on a leaf of a curved surface (some corner with a
  /// shading normal) every corner's leaves are evaluated at x's interpolated normal toward toEye and
  /// interpolated, so a highlight is as sharp as the directional basis, not the display vertices;
  /// elsewhere the corners' values, as radiance(leaf, x). Const and concurrent (still images).
  Rgb radiance(std::uint32_t leaf, const Vec3& x, const Vec3& toEye) const;
  bool simulated(std::uint32_t leaf) const { return cornerOf_[leaf] != kNone; }
  std::size_t vertexCount() const { return pos_.size(); }
  /// The leaf corners' values after update(), W/(m^2 sr): a simulated leaf's corners are the four
  /// from firstCorner(leaf) on (a triangle's fourth repeats its third), in its polygon's order.
  const std::vector<Rgb>& cornerValues() const { return cornerValue_; }
  std::uint32_t firstCorner(std::uint32_t leaf) const { return cornerOf_[leaf]; }
  /// Whether corner c changed in the last update() (the viewer uploads only those).
  bool cornerUpdated(std::uint32_t c) const { return fresh_[cornerVertex_[c]] != 0; }

 private:
  const Solution& s_;
  const Extension& ext_;
  std::vector<Vec3> pos_;                 // per display vertex
  std::vector<std::uint32_t> memberStart_, member_;  // leaves meeting at each vertex (CSR)
  std::vector<double> memberArea_;        // per member: its leaf's area, m^2 (the corners' weights)
  std::vector<Vec3> normal_;              // per display vertex: its shading normal, or 0 (each leaf its own)
  std::vector<char> curved_;              // per element: a simulated leaf with a shading normal at a corner
  std::vector<Rgb> value_;                // per member: radiance toward the eye, W/(m^2 sr)
  std::vector<std::uint32_t> cornerOf_;   // per element: first of its corners in corner*, or kNone
  std::vector<std::uint32_t> cornerVertex_;                  // per corner: its display vertex
  std::vector<std::uint32_t> useStart_, use_;                // per corner: members it averages (CSR)
  std::vector<Rgb> cornerValue_;          // per corner, after update()
  std::vector<glm::vec3> lastDir_;        // per vertex: the direction of its last evaluation (0: never)
  std::vector<char> fresh_;               // per vertex: re-evaluated by the last update()
};

}  // namespace hr
