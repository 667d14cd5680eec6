// solution.vtp through VTK's own XML writer, so ParaView reads exactly what VTK writes. Each leaf
// gets its own points, so the per-point smoothed radiosity of one leaf never bleeds across creases.
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataWriter.h>

#include <hr/output.h>
#include <hr/vtk_io.h>

namespace hr {

void writeVtp(const Solution& s, const std::string& path, const Extension* ext) {
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkDoubleArray> cellB, pointB, area;
  vtkNew<vtkIntArray> object, level, elementId;
  cellB->SetName("radiosity");
  cellB->SetNumberOfComponents(3);
  pointB->SetName("radiosity");
  pointB->SetNumberOfComponents(3);
  area->SetName("area");
  object->SetName("object_id");
  level->SetName("level");
  elementId->SetName("element_id");
  // With an extension: its coefficients and its reflected power per leaf (0 where it has none).
  vtkNew<vtkIntArray> coefficients;
  vtkNew<vtkDoubleArray> extPower;
  coefficients->SetName("directional_coefficients");
  extPower->SetName("directional_power_w");
  extPower->SetNumberOfComponents(3);
  for (std::uint32_t i = 0; i < s.elements.size(); ++i) {
    const auto& e = s.elements[i];
    if (!e.leaf()) continue;
    vtkIdType ids[4];
    for (int k = 0; k < e.poly.n; ++k) {
      ids[k] = pts->InsertNextPoint(e.poly.v[k].x, e.poly.v[k].y, e.poly.v[k].z);
      const Rgb& c = s.cornerRadiosity[i][k];
      pointB->InsertNextTuple3(c.x, c.y, c.z);
    }
    polys->InsertNextCell(e.poly.n, ids);
    cellB->InsertNextTuple3(e.radiosity.x, e.radiosity.y, e.radiosity.z);
    object->InsertNextValue(static_cast<int>(s.patches[e.patch].object));
    level->InsertNextValue(static_cast<int>(e.level));
    elementId->InsertNextValue(static_cast<int>(i));
    area->InsertNextValue(e.poly.area());
    if (ext) {
      coefficients->InsertNextValue(static_cast<int>(ext->coefficients(NodeId{i})));
      Rgb P = ext->reflectedPower(NodeId{i});
      extPower->InsertNextTuple3(P.x, P.y, P.z);
    }
  }
  vtkNew<vtkPolyData> pd;
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  pd->GetCellData()->AddArray(cellB);
  pd->GetCellData()->AddArray(object);
  pd->GetCellData()->AddArray(level);
  pd->GetCellData()->AddArray(elementId);
  pd->GetCellData()->AddArray(area);
  if (ext) {
    pd->GetCellData()->AddArray(coefficients);
    pd->GetCellData()->AddArray(extPower);
  }
  pd->GetPointData()->AddArray(pointB);
  writePolyData(pd, path);
}

void writePolyData(vtkPolyData* pd, const std::string& path) {
  writeAtomically(path, [&](const std::string& tmp) {
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetFileName(tmp.c_str());
    w->SetInputData(pd);
    w->SetDataModeToBinary();
    if (w->Write() != 1) throw std::runtime_error(path + ": VTK could not write the file");
  });
}

}  // namespace hr
