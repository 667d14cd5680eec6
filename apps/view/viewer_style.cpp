// The viewer's interactor style (see viewer_style.h).
#include "viewer_style.h"

#include <vtkObjectFactory.h>
#include <vtkRenderWindowInteractor.h>

#include "viewer.h"

namespace view {

vtkStandardNewMacro(ViewerStyle);

void ViewerStyle::OnKeyPress() {
  vtkRenderWindowInteractor* rwi = GetInteractor();
  std::string key = rwi->GetKeySym() ? rwi->GetKeySym() : "";
  if (key.empty() && rwi->GetKeyCode()) key = std::string(1, rwi->GetKeyCode());
  if (viewer_) viewer_->onKey(key);
}

void ViewerStyle::OnLeftButtonDown() {
  if (!viewer_ || !viewer_->walkMode()) return vtkInteractorStyleTrackballCamera::OnLeftButtonDown();
  looking_ = true;
  GetInteractor()->GetEventPosition(lastX_, lastY_);
}

void ViewerStyle::OnLeftButtonUp() {
  if (!looking_) return vtkInteractorStyleTrackballCamera::OnLeftButtonUp();
  looking_ = false;
}

void ViewerStyle::OnMouseMove() {
  if (!looking_) return vtkInteractorStyleTrackballCamera::OnMouseMove();
  int x, y;
  GetInteractor()->GetEventPosition(x, y);
  // A quarter of a degree per pixel: a 720-pixel drag turns the view by 180 degrees.
  viewer_->look(-0.25 * (x - lastX_), 0.25 * (y - lastY_));
  lastX_ = x, lastY_ = y;
}

}  // namespace view
