// The interactive window over a SceneView: a trackball (VTK's) and a first-person walk mode, the
// keys listed in the on-screen help (h), a HUD (fps, glossy update ms, vertices updated, glossy
// vertex count), A/B between glossy and diffuse-only display (g), picking with the element's lobe
// drawn as a glyph at the picked point (p), the scene's cameras (c), camera-path recording (r) and
// screenshots. Everything a key does is reachable through the interactor, so tests drive it with
// synthetic events under xvfb-run exactly as a person would.
#pragma once
#include <vtkActor.h>
#include <vtkRenderWindow.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>

#include <chrono>
#include <string>
#include <vector>

#include "camera_path.h"
#include "scene_view.h"

namespace view {

struct ViewerOptions {
  std::vector<hr::Camera> cameras;   // the scene's, cycled by c
  int startCamera = 0;
  int width = 960, height = 720;     // window size, pixels
  std::string recordPath = "camera_path.json";  // where r writes the recorded path
  std::string screenshotDir = ".";   // where screenshots go
  bool offscreen = false;            // tests: never mapped on the screen
};

class Viewer {
 public:
  Viewer(SceneView& scene, ViewerOptions opt);
  ~Viewer();
  /// Shows the window and runs the event loop until q, Escape or the window is closed.
  void run();

  vtkRenderWindowInteractor* interactor() const { return iren_; }
  vtkRenderWindow* window() const { return win_; }
  /// Renders one frame (the glossy update runs first, as for every frame).
  void render();

  // What the keys changed, for the HUD and for tests.
  bool helpShown() const;
  bool walkMode() const { return walk_; }
  int cameraIndex() const { return cameraIndex_; }
  bool recording() const { return recording_; }
  const CameraPath& recorded() const { return recorded_; }
  std::uint32_t pickedLeaf() const { return picked_; }
  const std::string& pickReport() const { return pickReport_; }
  vtkActor* glyph() const { return glyph_; }
  const std::string& lastScreenshot() const { return lastShot_; }
  const FrameStats& lastFrame() const { return last_; }
  std::string hudText() const;

  // Key actions (the interactor style calls these; public for the style only).
  void onKey(const std::string& key);
  void walkStep(double forward, double right);
  void look(double yawDeg, double pitchDeg);
  void pick(int x, int y);
  void screenshot();

 private:
  void beforeFrame();
  void afterFrame();
  void toggleRecording();
  void nextCamera();

  SceneView& scene_;
  ViewerOptions opt_;
  vtkSmartPointer<vtkRenderWindow> win_;
  vtkSmartPointer<vtkRenderWindowInteractor> iren_;
  vtkSmartPointer<vtkRenderer> overlay_;  // HUD and help, a layer above the scene's renderer
  vtkSmartPointer<vtkTextActor> hud_, help_;
  vtkSmartPointer<vtkActor> glyph_;
  bool walk_ = false, recording_ = false;
  int cameraIndex_ = 0;
  CameraPath recorded_;
  std::chrono::steady_clock::time_point recordStart_, lastFrameEnd_;
  std::uint32_t picked_ = hr::kNone;
  std::string pickReport_, lastShot_;
  FrameStats last_;
  double fps_ = 0.0;
  hr::Vec3 worldUp_{0.0, 1.0, 0.0};
};

}  // namespace view
