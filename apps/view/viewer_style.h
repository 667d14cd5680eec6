// The viewer's interactor style: VTK's trackball for the mouse (rotate, pan, zoom about the focal
// point), or in walk mode a first-person look (dragging turns the view about the eye); every key goes
// to Viewer::onKey, and VTK's own single-letter bindings (w: wireframe, s: surface, p: pick, e: exit,
// ...) are switched off so that they never fight the viewer's.
#pragma once
#include <vtkInteractorStyleTrackballCamera.h>

namespace view {

class Viewer;

class ViewerStyle : public vtkInteractorStyleTrackballCamera {
 public:
  static ViewerStyle* New();
  vtkTypeMacro(ViewerStyle, vtkInteractorStyleTrackballCamera)
  void setViewer(Viewer* v) { viewer_ = v; }

  void OnChar() override {}
  void OnKeyPress() override;
  void OnLeftButtonDown() override;
  void OnLeftButtonUp() override;
  void OnMouseMove() override;

 private:
  Viewer* viewer_ = nullptr;
  bool looking_ = false;
  int lastX_ = 0, lastY_ = 0;
};

}  // namespace view
