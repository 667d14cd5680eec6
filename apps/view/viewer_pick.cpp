// Picking (p): the surface point under the mouse, found by VTK's cell picker on the two lists (never
// on the glyph), its leaf reported as `glossyhr inspect` reports it (plus the radiance toward the
// eye there), and the leaf's exitant-intensity lobe drawn as a glyph rooted at the picked point,
// scaled so that its longest radius is a quarter of the scene's, coloured by its own RGB.
#include <vtkCellPicker.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkTransform.h>
#include <vtkUnsignedCharArray.h>

#include <cstdio>

#include "element_report.h"
#include "viewer.h"

namespace view {

namespace {

/// The lobe polydata, moved to x and scaled to `size` (m) at its longest, coloured by its RGB.
vtkSmartPointer<vtkActor> lobeGlyph(const std::vector<LobeArray>& lobe, const hr::Vec3& x, double size) {
  vtkSmartPointer<vtkPolyData> pd = lobeSurface(lobe, 5);
  double longest = 0.0;
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i) {
    double p[3];
    pd->GetPoint(i, p);
    longest = std::max(longest, std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]));
  }
  vtkDataArray* rgb = pd->GetPointData()->GetArray(lobe[0].name.c_str());
  double peak = 0.0;
  for (vtkIdType i = 0; i < rgb->GetNumberOfTuples(); ++i)
    for (int c = 0; c < 3; ++c) peak = std::max(peak, rgb->GetComponent(i, c));
  auto colours = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colours->SetName("colour");
  colours->SetNumberOfComponents(3);
  colours->SetNumberOfTuples(rgb->GetNumberOfTuples());
  for (vtkIdType i = 0; i < rgb->GetNumberOfTuples(); ++i)
    for (int c = 0; c < 3; ++c)
      colours->SetComponent(i, c, peak > 0.0 ? std::clamp(255.0 * std::sqrt(rgb->GetComponent(i, c) / peak), 0.0, 255.0) : 128.0);
  pd->GetPointData()->SetScalars(colours);
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputData(pd);
  mapper->SetColorModeToDirectScalars();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->SetPosition(x.x, x.y, x.z);
  const double scale = longest > 0.0 ? size / longest : 1.0;
  actor->SetScale(scale, scale, scale);
  actor->PickableOff();
  actor->GetProperty()->SetAmbient(0.5);  // a needle-thin glossy lobe stays visible against the light
  return actor;
}

}  // namespace

void Viewer::pick(int x, int y) {
  auto picker = vtkSmartPointer<vtkCellPicker>::New();
  picker->SetTolerance(0.0);
  picker->PickFromListOn();
  picker->AddPickList(scene_.diffuseActor());
  if (scene_.glossyActor()) picker->AddPickList(scene_.glossyActor());
  if (glyph_) {
    scene_.renderer()->RemoveActor(glyph_);
    glyph_ = nullptr;
  }
  picked_ = hr::kNone;
  pickReport_.clear();
  if (!picker->Pick(x, y, 0.0, scene_.renderer()) || !picker->GetActor()) {
    std::printf("pick: no surface under the mouse at (%d, %d)\n", x, y);
    return;
  }
  picked_ = scene_.leafOf(picker->GetActor(), picker->GetCellId());
  if (picked_ == hr::kNone) return;
  double p[3];
  picker->GetPickPosition(p);
  const hr::Vec3 at(p[0], p[1], p[2]);
  const hr::Solution& s = scene_.solution();
  ElementReport r = reportElement(s, scene_.extension(), picked_);
  // The radiance the pixel shows there: the host's smooth B / pi and the extension's share toward this eye.
  hr::Rgb diffuse = hr::interpolate(s, picked_, at) / hr::kPi;
  hr::Rgb glossy = scene_.glossyShown() ? scene_.glossyRadianceAt(picked_, at) : hr::Rgb(0.0);
  char b[256];
  std::snprintf(b, sizeof b, "  picked at (%.4g, %.4g, %.4g) m: radiance toward the eye %.4g %.4g %.4g W/(m^2 sr), of which glossy %.4g %.4g %.4g\n",
                at.x, at.y, at.z, diffuse.x + glossy.x, diffuse.y + glossy.y, diffuse.z + glossy.z, glossy.x, glossy.y, glossy.z);
  pickReport_ = r.text + b;
  std::printf("%s", pickReport_.c_str());
  glyph_ = lobeGlyph(elementLobe(s, scene_.extension(), picked_), at, 0.25 * scene_.sceneRadius());
  scene_.renderer()->AddActor(glyph_);
}

}  // namespace view
