// Coplanar overlap: a light panel modelled flush with a ceiling, a decal on a floor. Two surfaces in
// one plane facing the same way would both receive the light that reaches that spot (energy
// created: a flush floor lamp made 8-16 % out of nothing) and fight in images. The rule here: where
// they overlap, the smaller patch lies in front and its black back covers the larger one; faces in
// contact (one plane, opposite facing: a lamp lying on a box's bottom) hide each other, since light
// trapped between touching opaque faces is absorbed there. A patch a little in front of another,
// facing the same way (the Cornell box's lamp 1 mm under its ceiling), covers it too, whichever is
// the larger: the ceiling above the lamp gets no light through a slit a hundredth of the lamp's
// size, and averaging that dark part into the ceiling elements that straddle the lamp's outline
// showed their open part as a dark rim (2-3.5 % off on the ceiling, more with fewer rays per
// link). On the BRIGHT-like host links, the energy audit and images all ask the same question, so
// the answer is consistent; the VISION-like host asks it only to hide display cells
// (vision_host/src/export.cpp).
#pragma once
#include <hr/geometry.h>

#include <vector>

namespace hr {

/// The widest gap, as a share of the covering patch's size across (2 A / perimeter, not its radius:
/// light reaches under a long thin strip from its sides), at which a parallel patch in front of
/// another still covers it.
inline constexpr double kNearGap = 0.01;

class CoplanarCover {
 public:
  /// Finds, for every patch, the smaller same-facing patches in its plane, the same-facing ones just
  /// in front of it (kNearGap) and the opposite-facing ones in its plane whose interiors overlap it.
  /// tolerance: distance at which two planes count as one (m).
  CoplanarCover(const std::vector<Patch>& patches, double tolerance);
  /// The patch that covers point x of patch p, or kNone (almost always: no overlap at all).
  std::uint32_t coverOf(std::uint32_t p, const Vec3& x) const;
  /// Whether any patch covers part of patch p.
  bool covers(std::uint32_t p) const { return !cover_.empty() && first_[p + 1] > first_[p]; }
  bool any() const { return !cover_.empty(); }
  std::size_t pairs() const { return cover_.size(); }

 private:
  const std::vector<Patch>* patches_;
  std::vector<std::uint32_t> first_;  // per patch: start in cover_ (CSR), size patches + 1
  std::vector<std::uint32_t> cover_;
};

}  // namespace hr
