// Camera paths for walkthroughs: keyframes of eye, look-at, up, vertical field of view and time,
// read from and written to JSON, recorded in the viewer or written by hand, and interpolated
// smoothly (a cubic Hermite spline through the keyframes, Catmull-Rom tangents over non-uniform
// times), so that a replay passes through every keyframe exactly and never jumps. Free of VTK: the
// display benchmark reads paths too.
#pragma once
#include <hr/scene.h>

#include <string>
#include <vector>

namespace view {

struct Keyframe {
  double time = 0.0;  // s, strictly increasing along a path
  hr::Vec3 eye{0.0}, lookAt{0.0, 0.0, -1.0}, up{0.0, 1.0, 0.0};
  double fovYDeg = 45.0;
};

struct CameraPath {
  std::vector<Keyframe> keys;
  double fps = 30.0;         // frames per second of a replay
  int width = 0, height = 0;  // pixels; 0: the start camera's
  double duration() const { return keys.empty() ? 0.0 : keys.back().time - keys.front().time; }
  /// Frames of a replay: one at the first key's time and every 1/fps s after, the last at or
  /// before the last key's time.
  int frameCount() const;
  double frameTime(int frame) const { return keys.front().time + frame / fps; }
};

/// Reads and validates a path file (strict JSON: unknown or repeated keys are refused). Throws
/// hr::InputError naming the file and the key (e.g. "keyframes[2].eye").
CameraPath loadCameraPath(const std::string& path);
CameraPath parseCameraPath(const std::string& text, const std::string& file);
/// Checks every rule loadCameraPath checks; throws hr::InputError naming `file` and the key.
void validateCameraPath(const CameraPath& p, const std::string& file);
/// The JSON text of a path (what the recorder writes, what loadCameraPath reads).
std::string cameraPathJson(const CameraPath& p);

/// The camera at time t (clamped to the path's span), with the given image size.
hr::Camera cameraAt(const CameraPath& p, double t, int width, int height);

}  // namespace view
