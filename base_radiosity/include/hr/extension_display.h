// The extension's share of a saved solution's display, smooth across elements (paper §5.2): the
// corners of the leaves an extension simulates meet in display vertices (one per position, object and
// material: never blended across objects, materials or creases), each vertex's adjacent leaves are
// evaluated toward the eye, and a leaf corner takes the area-weighted mean of those within 30 degrees
// of its own normal. Still images and the viewer use the same values, so they agree.
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
  void update(const Vec3& eye);
  /// The extension's radiance at x on a leaf, W/(m^2 sr): its corners' values interpolated. Zero
  /// for leaves the extension does not simulate.
  Rgb radiance(std::uint32_t leaf, const Vec3& x) const;
  bool simulated(std::uint32_t leaf) const { return cornerOf_[leaf] != kNone; }
  std::size_t vertexCount() const { return pos_.size(); }

 private:
  const Solution& s_;
  const Extension& ext_;
  std::vector<Vec3> pos_;                 // per display vertex
  std::vector<std::uint32_t> memberStart_, member_;  // leaves meeting at each vertex (CSR)
  std::vector<Rgb> value_;                // per member: radiance toward the eye, W/(m^2 sr)
  std::vector<std::uint32_t> cornerOf_;   // per element: first of its corners in corner*, or kNone
  std::vector<std::uint32_t> cornerVertex_;                  // per corner: its display vertex
  std::vector<std::uint32_t> useStart_, use_;                // per corner: members it averages (CSR)
  std::vector<Rgb> cornerValue_;          // per corner, after update()
};

}  // namespace hr
