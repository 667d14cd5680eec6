// A saved solution as VTK actors: the diffuse list uploaded once and never touched again, the glossy
// list whose per-vertex radiance is re-evaluated toward the eye before each frame (only the display
// vertices whose view direction turned by more than the threshold, in parallel), both tone-mapped per
// pixel with one exposure for the whole session. Used by the interactive window and by headless
// walkthroughs alike, so both show the same pixels.
#pragma once
#include <hr/extension_display.h>
#include <hr/solution.h>
#include <vtkActor.h>
#include <vtkFloatArray.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include <memory>

#include "display_lists.h"

namespace view {

struct FrameStats {
  double glossyMs = 0.0;          // re-evaluation and the copy into the vertex array, ms (wall)
  std::size_t verticesUpdated = 0;  // display vertices re-evaluated this frame
};

class SceneView {
 public:
  /// ext may be null (a diffuse solution: the glossy list is empty). Both must outlive the view.
  SceneView(const hr::Solution& s, const hr::Extension* ext, double exposure);
  vtkRenderer* renderer() const { return renderer_; }

  /// Points the renderer's camera at c (eye, look-at, up, vertical field of view).
  void setCamera(const hr::Camera& c);
  /// The renderer's camera now, as a keyframe would hold it (size from the arguments).
  hr::Camera camera(int width, int height) const;
  /// Re-evaluates the glossy list toward the camera's eye (call before each render).
  FrameStats updateGlossy();

  void setThresholdDeg(double deg) { thresholdDeg_ = deg; }
  double thresholdDeg() const { return thresholdDeg_; }
  /// Glossy (the extension's light added) or the diffuse-only display of the same solution.
  void showGlossy(bool on);
  bool glossyShown() const { return glossyShown_; }
  double exposure() const { return exposure_; }

  /// Display vertices of the extension's leaves (the count the paper's per-frame work scales with).
  std::size_t glossyVertexCount() const { return display_ ? display_->vertexCount() : 0; }
  /// The leaf a picked cell of one of the two actors shows, or hr::kNone.
  std::uint32_t leafOf(vtkActor* actor, vtkIdType cell) const;
  /// The extension's radiance the glossy list shows at x on a leaf now, W/(m^2 sr).
  hr::Rgb glossyRadianceAt(std::uint32_t leaf, const hr::Vec3& x) const {
    return display_ ? display_->radiance(leaf, x) : hr::Rgb(0.0);
  }
  vtkActor* diffuseActor() const { return diffuseActor_; }
  vtkActor* glossyActor() const { return glossyActor_; }
  const hr::Solution& solution() const { return s_; }
  const hr::Extension* extension() const { return ext_; }
  /// Radius of the scene's bounding sphere, m (walking steps and glyph sizes scale with it).
  double sceneRadius() const { return radius_; }

 private:
  const hr::Solution& s_;
  const hr::Extension* ext_;
  std::unique_ptr<hr::ExtensionDisplay> display_;
  DisplayLists lists_;
  vtkSmartPointer<vtkRenderer> renderer_;
  vtkSmartPointer<vtkActor> diffuseActor_, glossyActor_;
  vtkSmartPointer<vtkFloatArray> glossyRadiance_;
  double exposure_, thresholdDeg_ = 0.0, radius_ = 1.0;
  bool glossyShown_ = true;
};

/// The exposure of the PNG that `solve` and `glossyhr render` write for camera c: 0.18 over the
/// log-average luminance of hr::render's image of it (hr::pngExposure).
double stillExposure(const hr::Solution& s, const hr::Extension* ext, const hr::Camera& c);

}  // namespace view
