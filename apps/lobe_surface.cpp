// Lobe surfaces (see lobe_surface.h): a subdivided tetrahedron as the sphere.
#include "lobe_surface.h"

#include <glossy/tetra.h>
#include <hr/vtk_io.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <algorithm>

vtkSmartPointer<vtkPolyData> lobeSurface(const std::vector<LobeArray>& arrays, int level) {
  const glossy::TetraMesh& m = glossy::TetraMesh::get(level);
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  std::vector<vtkNew<vtkDoubleArray>> data(arrays.size());
  for (std::size_t a = 0; a < arrays.size(); ++a) {
    data[a]->SetName(arrays[a].name.c_str());
    data[a]->SetNumberOfComponents(3);
  }
  for (std::size_t i = 0; i < m.vertexCount(); ++i) {
    const hr::Vec3& v = m.vertex(i);
    for (std::size_t a = 0; a < arrays.size(); ++a) {
      hr::Rgb p = arrays[a].value(v);
      if (!hr::allFinite(p)) p = hr::Rgb(0.0);
      if (a == 0) {
        double r = std::max(0.0, hr::luminance(p));  // spherical harmonics may ring below zero
        pts->InsertNextPoint(r * v.x, r * v.y, r * v.z);
      }
      data[a]->InsertNextTuple3(p.x, p.y, p.z);
    }
  }
  vtkNew<vtkCellArray> polys;
  for (std::size_t t = 0; t < m.triangleCount(); ++t) {
    const auto& tri = m.triangle(t);
    vtkIdType ids[3] = {vtkIdType(tri[0]), vtkIdType(tri[1]), vtkIdType(tri[2])};
    polys->InsertNextCell(3, ids);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  for (auto& d : data) pd->GetPointData()->AddArray(d);
  if (!arrays.empty()) pd->GetPointData()->SetActiveScalars(arrays[0].name.c_str());
  return pd;
}

void writeLobeSurface(const std::string& path, const std::vector<LobeArray>& arrays) {
  hr::writePolyData(lobeSurface(arrays, 7), path);
}
