// The solution's actors and the per-frame glossy update (see scene_view.h).
#include "scene_view.h"

#include <hr/output.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkIdTypeArray.h>
#include <vtkOpenGLPolyDataMapper.h>
#include <vtkPointData.h>
#include <vtkPoints.h>

#include <chrono>

#include "tone_shader.h"

namespace view {

namespace {

vtkSmartPointer<vtkFloatArray> floats(const char* name, const std::vector<float>& v) {
  auto a = vtkSmartPointer<vtkFloatArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(3);
  a->SetNumberOfTuples(static_cast<vtkIdType>(v.size() / 3));
  std::copy(v.begin(), v.end(), a->GetPointer(0));
  return a;
}

vtkSmartPointer<vtkActor> makeActor(const DisplayList& l, bool glossy, double exposure, vtkFloatArray* glossyArray) {
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  auto pts = vtkSmartPointer<vtkPoints>::New();
  pts->SetData(floats("points", l.points));
  pd->SetPoints(pts);
  auto offsets = vtkSmartPointer<vtkIdTypeArray>::New(), conn = vtkSmartPointer<vtkIdTypeArray>::New();
  offsets->SetNumberOfTuples(static_cast<vtkIdType>(l.triangleLeaf.size() + 1));
  conn->SetNumberOfTuples(static_cast<vtkIdType>(l.triangles.size()));
  for (std::size_t t = 0; t <= l.triangleLeaf.size(); ++t) offsets->SetValue(vtkIdType(t), vtkIdType(3 * t));
  for (std::size_t i = 0; i < l.triangles.size(); ++i) conn->SetValue(vtkIdType(i), vtkIdType(l.triangles[i]));
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->SetData(offsets, conn);
  pd->SetPolys(cells);
  pd->GetPointData()->AddArray(floats("diffuse_radiance", l.diffuse));
  if (glossy) pd->GetPointData()->AddArray(glossyArray);
  auto mapper = vtkSmartPointer<vtkOpenGLPolyDataMapper>::New();
  mapper->SetInputData(pd);
  mapper->StaticOn();  // the input never changes shape: no pipeline update per frame
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  installToneShader(actor, glossy, exposure);
  return actor;
}

}  // namespace

SceneView::SceneView(const hr::Solution& s, const hr::Extension* ext, double exposure) : s_(s), ext_(ext), exposure_(exposure) {
  if (ext) display_ = std::make_unique<hr::ExtensionDisplay>(s, *ext);
  lists_ = buildDisplayLists(s, display_.get());
  hr::Aabb box;
  for (const hr::Patch& p : s.patches)
    for (int k = 0; k < p.poly.n; ++k) box.grow(p.poly.v[k]);
  radius_ = std::max(0.5 * box.diagonal(), 1e-6);
  renderer_ = vtkSmartPointer<vtkRenderer>::New();
  renderer_->SetBackground(0.0, 0.0, 0.0);  // hr::render leaves missed rays black
  diffuseActor_ = makeActor(lists_.diffuse, false, exposure, nullptr);
  renderer_->AddActor(diffuseActor_);
  glossyRadiance_ = floats("glossy_radiance", std::vector<float>(lists_.glossy.points.size(), 0.0f));
  if (lists_.glossy.vertexCount() > 0) {
    glossyActor_ = makeActor(lists_.glossy, true, exposure, glossyRadiance_);
    renderer_->AddActor(glossyActor_);
  }
}

void SceneView::setCamera(const hr::Camera& c) {
  vtkCamera* cam = renderer_->GetActiveCamera();
  cam->SetPosition(c.eye.x, c.eye.y, c.eye.z);
  cam->SetFocalPoint(c.lookAt.x, c.lookAt.y, c.lookAt.z);
  cam->SetViewUp(c.up.x, c.up.y, c.up.z);
  cam->SetViewAngle(c.fovYDeg);
  cam->OrthogonalizeViewUp();
  renderer_->ResetCameraClippingRange();
}

hr::Camera SceneView::camera(int width, int height) const {
  vtkCamera* cam = renderer_->GetActiveCamera();
  hr::Camera c;
  c.name = "view";
  double v[3];
  cam->GetPosition(v), c.eye = {v[0], v[1], v[2]};
  cam->GetFocalPoint(v), c.lookAt = {v[0], v[1], v[2]};
  cam->GetViewUp(v), c.up = {v[0], v[1], v[2]};
  c.fovYDeg = cam->GetViewAngle();
  c.width = width;
  c.height = height;
  return c;
}

FrameStats SceneView::updateGlossy() {
  FrameStats st;
  if (!display_ || !glossyActor_) return st;
  auto t0 = std::chrono::steady_clock::now();
  double e[3];
  renderer_->GetActiveCamera()->GetPosition(e);
  st.verticesUpdated = display_->update(hr::Vec3(e[0], e[1], e[2]), thresholdDeg_);
  if (st.verticesUpdated > 0) {
    glossyRadiance(lists_.glossy, *display_, glossyRadiance_->GetPointer(0));
    glossyRadiance_->Modified();
  }
  st.glossyMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  renderer_->ResetCameraClippingRange();
  return st;
}

void SceneView::showGlossy(bool on) {
  glossyShown_ = on;
  if (glossyActor_) setGlossyWeight(glossyActor_, on ? 1.0 : 0.0);
}

std::uint32_t SceneView::leafOf(vtkActor* actor, vtkIdType cell) const {
  const DisplayList* l = actor == diffuseActor_.Get() ? &lists_.diffuse : actor == glossyActor_.Get() ? &lists_.glossy : nullptr;
  if (!l || cell < 0 || std::size_t(cell) >= l->triangleLeaf.size()) return hr::kNone;
  return l->triangleLeaf[std::size_t(cell)];
}

double stillExposure(const hr::Solution& s, const hr::Extension* ext, const hr::Camera& c) {
  return hr::pngExposure(hr::render(s, c, ext));
}

}  // namespace view
