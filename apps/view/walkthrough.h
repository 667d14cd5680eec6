// Headless replay of a camera path: every frame rendered off screen at the path's times, written as
// numbered PNGs (stills, as `glossyhr render` draws them; with --benchmark the timed frames as the
// window draws them) through an output set (all frames appear together or none, and a frames folder this
// run created is removed again when it fails), optionally encoded to a video with ffmpeg, optionally
// timed per frame (the CSV and summary of --benchmark).
#pragma once
#include <string>
#include <vector>

#include "camera_path.h"
#include "scene_view.h"

namespace view {

/// Samples per pixel and axis of a still (hr::render's grid).
inline constexpr int kStillSamples = 3;

struct WalkthroughOptions {
  std::string framesDir;  // PNGs (and timings with benchmark); empty: frames are rendered, not kept
  std::string video;      // .mp4 to encode with ffmpeg; empty: none
  bool benchmark = false;
  bool quiet = false;
};

struct FrameTiming {
  double totalMs = 0.0, glossyMs = 0.0;  // wall-clock ms: the whole frame (update, upload, draw, finish), the glossy update
  std::size_t verticesUpdated = 0;
};

struct TimingSummary {
  double median = 0.0, p95 = 0.0, max = 0.0;  // ms
};
TimingSummary summarize(std::vector<double> ms);

/// The frame file name of frame i (frame_00000.png ...).
std::string frameName(int i);
/// Where ffmpeg is on PATH, or empty.
std::string findFfmpeg();

/// Renders the path (width x height pixels). Throws hr::InputError for unusable outputs and
/// EnvironmentError when ffmpeg is missing for a video. Returns the per-frame timings.
std::vector<FrameTiming> runWalkthrough(SceneView& scene, const CameraPath& path, int width, int height,
                                        const WalkthroughOptions& opt);

}  // namespace view
