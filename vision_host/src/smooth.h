// Per-vertex smoothing of the VISION-like host's display in each primitive's parameter space (see
// smooth.cpp): the radiosity at the four parameter corners of every leaf, which export.cpp
// interpolates bilinearly in (u, v) over the leaf's display cells.
#pragma once
#include <vision/hierarchy.h>

#include <array>
#include <vector>

namespace vision {

/// Corner order: (u0, v0), (u1, v0), (u1, v1), (u0, v1).
using LeafCorners = std::array<Rgb, 4>;

/// leaves: every leaf of every surface, hidden[i]: leaf i lies under a surface just in front of it
/// (its light must not spread onto visible neighbours). Returns the corners per leaf, W/m^2.
std::vector<LeafCorners> smoothCorners(const Hierarchy& h, const std::vector<const Element*>& leaves,
                                       const std::vector<char>& hidden);

}  // namespace vision
