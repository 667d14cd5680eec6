// The interactive viewer (see viewer.h): window, HUD, keys, recording and screenshots. Picking and
// the lobe glyph are in viewer_pick.cpp, the mouse and key routing in viewer_style.cpp.
#include "viewer.h"

#include <hr/output.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkRenderer.h>
#include <vtkTextProperty.h>

#include <cstdio>
#include <filesystem>

#include "still.h"
#include "viewer_style.h"
#include "walkthrough.h"
#include "window.h"

namespace fs = std::filesystem;

namespace view {

namespace {

const char* kHelp =
    "h  help on/off\n"
    "mouse  trackball: left rotate, middle pan, right/wheel zoom\n"
    "f  walk mode on/off (left drag looks around)\n"
    "w/a/s/d  walk (in walk mode; s walks back there)\n"
    "g  glossy / diffuse-only display\n"
    "p  pick the surface under the mouse: its lobe\n"
    "c  next scene camera\n"
    "r  start/stop recording the camera path\n"
    "s  screenshot (trackball mode), x screenshot (any mode)\n"
    "q, Esc  quit";

vtkSmartPointer<vtkTextActor> text(int x, int y, bool top) {
  auto t = vtkSmartPointer<vtkTextActor>::New();
  t->GetTextProperty()->SetFontSize(14);
  t->GetTextProperty()->SetColor(1.0, 1.0, 0.6);
  t->GetTextProperty()->SetFontFamilyToCourier();
  if (top) t->GetTextProperty()->SetVerticalJustificationToTop();
  t->SetDisplayPosition(x, y);
  return t;
}

/// Calls (self->*fn)() on each `event` of o.
template <class F>
void observe(vtkObject* o, unsigned long event, F* self, void (F::*fn)()) {
  struct Thunk {
    F* self;
    void (F::*fn)();
  };
  auto cb = vtkSmartPointer<vtkCallbackCommand>::New();
  cb->SetClientData(new Thunk{self, fn});
  cb->SetCallback([](vtkObject*, unsigned long, void* data, void*) {
    auto* t = static_cast<Thunk*>(data);
    (t->self->*(t->fn))();
  });
  cb->SetClientDataDeleteCallback([](void* data) { delete static_cast<Thunk*>(data); });
  o->AddObserver(event, cb);
}

}  // namespace

Viewer::Viewer(SceneView& scene, ViewerOptions opt) : scene_(scene), opt_(std::move(opt)) {
  win_ = makeWindow(opt_.width, opt_.height, opt_.offscreen);
  win_->AddRenderer(scene_.renderer());
  iren_ = vtkSmartPointer<vtkRenderWindowInteractor>::New();
  iren_->SetRenderWindow(win_);
  auto style = vtkSmartPointer<ViewerStyle>::New();
  style->setViewer(this);
  iren_->SetInteractorStyle(style);
  hud_ = text(8, 8, false);
  help_ = text(8, opt_.height - 8, true);
  help_->SetInput(kHelp);
  help_->SetVisibility(0);
  // The HUD lives in a layer of this window only: the scene's renderer, which walkthroughs also draw,
  // holds nothing but the scene.
  overlay_ = vtkSmartPointer<vtkRenderer>::New();
  overlay_->SetLayer(1);
  overlay_->InteractiveOff();
  overlay_->AddActor2D(hud_);
  overlay_->AddActor2D(help_);
  win_->SetNumberOfLayers(2);
  win_->AddRenderer(overlay_);
  cameraIndex_ = opt_.startCamera;
  if (!opt_.cameras.empty()) {
    scene_.setCamera(opt_.cameras[std::size_t(cameraIndex_)]);
    worldUp_ = glm::normalize(opt_.cameras[std::size_t(cameraIndex_)].up);
  }
  observe(win_.Get(), vtkCommand::StartEvent, this, &Viewer::beforeFrame);
  observe(win_.Get(), vtkCommand::EndEvent, this, &Viewer::afterFrame);
  iren_->Initialize();
  lastFrameEnd_ = std::chrono::steady_clock::now();
}

Viewer::~Viewer() {
  win_->RemoveAllObservers();
  win_->RemoveRenderer(overlay_);
  if (glyph_) scene_.renderer()->RemoveActor(glyph_);
  win_->RemoveRenderer(scene_.renderer());
  win_->Finalize();
}

void Viewer::run() {
  std::printf("glossyhr view: h shows the keys; %zu glossy display vertices, exposure %.6g\n", scene_.glossyVertexCount(),
              scene_.exposure());
  render();
  iren_->Start();
}

void Viewer::render() { win_->Render(); }

bool Viewer::helpShown() const { return help_->GetVisibility() != 0; }

std::string Viewer::hudText() const {
  char b[256];
  std::snprintf(b, sizeof b, "%.1f fps | glossy update %.2f ms | %zu vertices updated | %zu glossy vertices | %s%s%s",
                fps_, last_.glossyMs, last_.verticesUpdated, scene_.glossyVertexCount(),
                scene_.glossyShown() ? "glossy" : "diffuse only", walk_ ? " | walk" : "", recording_ ? " | REC" : "");
  return b;
}

void Viewer::beforeFrame() {
  last_ = scene_.updateGlossy();
  hud_->SetInput(hudText().c_str());
}

void Viewer::afterFrame() {
  auto now = std::chrono::steady_clock::now();
  double dt = std::chrono::duration<double>(now - lastFrameEnd_).count();
  lastFrameEnd_ = now;
  if (dt > 0.0) fps_ = fps_ > 0.0 ? 0.9 * fps_ + 0.1 / dt : 1.0 / dt;  // smoothed over about ten frames
  if (!recording_) return;
  const int* size = win_->GetSize();
  hr::Camera c = scene_.camera(size[0], size[1]);
  const Keyframe& lastKey = recorded_.keys.back();
  if (c.eye == lastKey.eye && c.lookAt == lastKey.lookAt && c.up == lastKey.up && c.fovYDeg == lastKey.fovYDeg) return;
  // Times from the clock, strictly increasing even when frames come faster than it ticks.
  double t = std::max(std::chrono::duration<double>(now - recordStart_).count(), lastKey.time + 1e-3);
  recorded_.keys.push_back({t, c.eye, c.lookAt, c.up, c.fovYDeg});
}

void Viewer::onKey(const std::string& key) {
  if (key == "h") {
    help_->SetVisibility(!help_->GetVisibility());
  } else if (key == "g") {
    scene_.showGlossy(!scene_.glossyShown());
  } else if (key == "f") {
    walk_ = !walk_;
  } else if (key == "p") {
    int x, y;
    iren_->GetEventPosition(x, y);
    pick(x, y);
  } else if (key == "c") {
    nextCamera();
  } else if (key == "r") {
    toggleRecording();
  } else if (key == "x" || (key == "s" && !walk_)) {
    screenshot();
    return;
  } else if (key == "w" || key == "Up") {
    walkStep(1.0, 0.0);
  } else if (key == "s" || key == "Down") {
    walkStep(-1.0, 0.0);
  } else if (key == "a" || key == "Left") {
    walkStep(0.0, -1.0);
  } else if (key == "d" || key == "Right") {
    walkStep(0.0, 1.0);
  } else if (key == "q" || key == "Escape") {
    iren_->TerminateApp();
    return;
  } else {
    return;
  }
  render();
}

void Viewer::walkStep(double forward, double right) {
  vtkCamera* cam = scene_.renderer()->GetActiveCamera();
  double p[3], f[3];
  cam->GetPosition(p);
  cam->GetFocalPoint(f);
  hr::Vec3 eye(p[0], p[1], p[2]), at(f[0], f[1], f[2]);
  hr::Vec3 dir = glm::normalize(at - eye);
  // Walking keeps the eye's height: forward is the view direction flattened onto the floor.
  hr::Vec3 ahead = dir - glm::dot(dir, worldUp_) * worldUp_;
  ahead = glm::length(ahead) > 1e-6 ? glm::normalize(ahead) : dir;
  hr::Vec3 side = glm::normalize(glm::cross(ahead, worldUp_));
  hr::Vec3 step = 0.02 * scene_.sceneRadius() * (forward * ahead + right * side);
  eye += step, at += step;
  cam->SetPosition(eye.x, eye.y, eye.z);
  cam->SetFocalPoint(at.x, at.y, at.z);
}

void Viewer::look(double yawDeg, double pitchDeg) {
  vtkCamera* cam = scene_.renderer()->GetActiveCamera();
  cam->SetViewUp(worldUp_.x, worldUp_.y, worldUp_.z);
  cam->Yaw(yawDeg);
  cam->Pitch(pitchDeg);
  // Never over the top: the view stays within 85 degrees of the horizon, the world's up stays up.
  double d[3];
  cam->GetDirectionOfProjection(d);
  if (std::abs(glm::dot(hr::Vec3(d[0], d[1], d[2]), worldUp_)) > std::cos(5.0 * hr::kPi / 180.0)) cam->Pitch(-pitchDeg);
  cam->SetViewUp(worldUp_.x, worldUp_.y, worldUp_.z);
  cam->OrthogonalizeViewUp();
  render();
}

void Viewer::nextCamera() {
  if (opt_.cameras.empty()) {
    std::printf("this solution has no cameras\n");
    return;
  }
  cameraIndex_ = (cameraIndex_ + 1) % int(opt_.cameras.size());
  const hr::Camera& c = opt_.cameras[std::size_t(cameraIndex_)];
  scene_.setCamera(c);
  worldUp_ = glm::normalize(c.up);
  std::printf("camera \"%s\"\n", c.name.c_str());
}

void Viewer::toggleRecording() {
  const int* size = win_->GetSize();
  if (!recording_) {
    recording_ = true;
    recordStart_ = std::chrono::steady_clock::now();
    hr::Camera c = scene_.camera(size[0], size[1]);
    recorded_ = CameraPath{};
    recorded_.width = size[0];
    recorded_.height = size[1];
    recorded_.keys.push_back({0.0, c.eye, c.lookAt, c.up, c.fovYDeg});
    std::printf("recording the camera path (r stops)\n");
    return;
  }
  recording_ = false;
  hr::writeFileAtomically(opt_.recordPath, cameraPathJson(recorded_));
  std::printf("camera path of %zu keyframes, %.2f s, written to %s\n", recorded_.keys.size(), recorded_.duration(),
              opt_.recordPath.c_str());
}

void Viewer::screenshot() {
  // A still without HUD and help, as `glossyhr render` would draw it: the scene's renderer visits an
  // offscreen window of three times the size for it.
  const int* size = win_->GetSize();
  const int w = size[0], h = size[1];
  win_->RemoveRenderer(scene_.renderer());
  std::vector<unsigned char> rgb = renderStill(scene_.renderer(), w, h, kStillSamples, scene_.exposure());
  win_->AddRenderer(scene_.renderer());
  fs::path file;
  for (int i = 0;; ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "screenshot_%03d.png", i);
    file = fs::path(opt_.screenshotDir) / name;
    if (!fs::exists(file)) break;
  }
  hr::writePng8(rgb, w, h, file.string());
  lastShot_ = file.string();
  std::printf("screenshot written to %s\n", lastShot_.c_str());
  render();
}

}  // namespace view
