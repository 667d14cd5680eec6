// Writing VTK XML PolyData atomically, for every .vtp the project writes (solutions, lobes). Only
// code that links hr_vtk includes this; the rest of the core never sees VTK.
#pragma once
#include <string>

class vtkPolyData;

namespace hr {

/// Writes pd as binary VTK XML PolyData to path through a temporary file and a rename.
void writePolyData(vtkPolyData* pd, const std::string& path);

}  // namespace hr
