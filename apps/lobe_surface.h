// A directional function drawn as a VTK surface (ParaView): a fine sphere whose radius in each
// direction is the luminance of the first function, with every function's RGB value as a point array.
// Used by `glossyhr lobe` (a projected lobe beside the analytic one) and `glossyhr inspect` (an
// element's exitant intensity).
#pragma once
#include <hr/types.h>

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <functional>
#include <string>
#include <vector>

struct LobeArray {
  std::string name;
  std::function<hr::Rgb(const hr::Vec3&)> value;  // unit direction -> RGB
};

/// The surface on the subdivided tetrahedron of the given level (7: 65538 directions); arrays[0]
/// sets the radius (its luminance, so W/sr become metres: scale it for display).
vtkSmartPointer<vtkPolyData> lobeSurface(const std::vector<LobeArray>& arrays, int level = 7);
/// Writes the level-7 surface to path (.vtp, atomically).
void writeLobeSurface(const std::string& path, const std::vector<LobeArray>& arrays);
