// A directional function drawn as a VTK surface (ParaView): a fine sphere whose radius in each
// direction is the luminance of the first function, with every function's RGB value as a point array.
// Used by `glossyhr lobe` (a projected lobe beside the analytic one) and `glossyhr inspect` (an
// element's exitant intensity).
#pragma once
#include <hr/types.h>

#include <functional>
#include <string>
#include <vector>

struct LobeArray {
  std::string name;
  std::function<hr::Rgb(const hr::Vec3&)> value;  // unit direction -> RGB
};

/// Writes the surface to path (.vtp, atomically); arrays[0] sets the radius.
void writeLobeSurface(const std::string& path, const std::vector<LobeArray>& arrays);
