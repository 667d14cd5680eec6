// The finest Haar level a glossy material's distributions are refined to when --dir-max-level is not
// given: tied to the width of its Phong lobe, so that sharp materials get fine cells and broad ones
// stay coarse (one global level either smears a sharp lobe or pays fine cells for broad ones: the
// three-lights reflector, n = 500, needs level 5; the glossy Cornell floor, n = 60, is served by 3).
//
// Rule: the coarsest level L whose cells' angular size, sqrt(solid angle) = sqrt(pi/2) / 2^L rad
// (eight octants of pi/2 sr, each split 1 -> 4 per level), is no larger than the lobe's 1/e half-width
// sqrt(2/n) (constant 1): L = ceil(log2(pi n / 4) / 2). Then the lobe's 1/e cap (pi w^2) spans at
// least pi cells, so the peak is placed to within less than its half-width. n = 60 -> 3, 300 -> 4,
// 500 -> 5. Clamped to [max(dir-min-level, 3), 5]: 3 is the former global default (no material is held
// coarser than before, whose figures stand), 5 bounds the memory (each level is 4x the cells a lobe
// may refine to) and is where the measured gain on three lights ends (docs/glossy.md).
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>

namespace glossy {

/// A Phong lobe cos^n's 1/e half-width from the mirror direction, sqrt(2/n) rad, at most pi/2.
inline double lobeWidth(double exponent) {
  return exponent > 0.0 ? std::min(0.5 * std::numbers::pi, std::sqrt(2.0 / exponent)) : 0.5 * std::numbers::pi;
}

inline constexpr int kLobeLevelCoarsest = 3;
inline constexpr int kLobeLevelFinest = 5;

/// The level for Phong exponent n (>= 0; a non-finite or negative one gets the coarsest) and the
/// configured dir-min-level.
int lobeLevel(double exponent, int minLevel);

}  // namespace glossy
