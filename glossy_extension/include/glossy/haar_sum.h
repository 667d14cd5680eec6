// The pull of the Haar basis: a parent's distribution is the sum of its children's (paper §3.3), but
// the plain union of adaptive trees grows with every child (64 exponent-100 lobes reached 230,792
// nodes in one parent). The sum is therefore re-projected top-down with the same relative refiner the
// leaves use, on exact cell means instead of point samples: a cell is split only where the means of
// its four sub-cells differ by more than eps relative to its own mean. Children may be held in other
// frames (a cluster over differently oriented elements); their means over a parent cell are then
// computed exactly by clipping their cells against it. Every value is an exact mean, so the power of
// the sum is exact up to float rounding.
#pragma once
#include <glossy/frame.h>
#include <glossy/haar.h>

#include <cstdint>
#include <span>

namespace glossy {

/// One child: a non-negative distribution and the frame it is stored in.
struct HaarTerm {
  const HaarDistribution* tree = nullptr;
  Frame frame;
};

/// Cells the last sum visited (its work) and the rotated cells it clipped.
struct HaarSumStats {
  std::uint64_t cells = 0, clips = 0;
};

/// The sum of the terms as one tree in `target`'s frame. Uses o.eps, o.minLevel (only where the
/// sub-cell means differ), o.maxLevel, o.refiner and o.floor (relative to the sum of the terms' peaks).
/// horizon: target is a leaf's own frame, and what the terms hold below its plane (z < 0) is dropped:
/// a surface sends nothing there, and a saved leaf must hold nothing there.
HaarDistribution haarSum(std::span<const HaarTerm> terms, const Frame& target, const HaarOptions& o,
                         HaarSumStats* stats = nullptr, bool horizon = false);

}  // namespace glossy
