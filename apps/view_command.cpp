// The view command (see view_command.h).
#include "view_command.h"

#include <hr/echo.h>
#include <hr/limits.h>
#include <hr/solution_view.h>
#include <tbb/global_control.h>

#include <cstdio>
#include <filesystem>
#include <thread>

#include "extension_cli.h"
#include "flag_checks.h"
#include "view/camera_path.h"
#include "view/scene_view.h"
#include "view/viewer.h"
#include "view/walkthrough.h"
#include "view/window.h"

namespace fs = std::filesystem;

namespace {

constexpr hr::limits::Range kThresholdDeg{"angle threshold", 0.0, 180.0};
constexpr hr::limits::Range kExposure{"exposure", 1e-30, 1e30};

hr::Camera startCamera(const ViewArgs& a, const hr::Solution& sol) {
  std::string names;
  for (const auto& c : sol.cameras) names += (names.empty() ? "" : ", ") + c.name;
  for (const auto& c : sol.cameras)
    if (a.camera.empty() || c.name == a.camera) return c;
  if (a.camera.empty()) throw hr::InputError(a.solution + ": the solution has no camera");
  throw hr::InputError("--camera: no camera " + hr::echo(a.camera) + " in " + a.solution + " (cameras: " +
                       hr::clipMessage(names, 400) + ")");
}

void checkFlags(const ViewArgs& a) {
  checkFlag("--angle-threshold", a.angleThreshold, kThresholdDeg);
  checkFlag("--exposure", a.exposure, kExposure);
  checkFlag("--width", a.width, hr::limits::kImageSize);
  checkFlag("--height", a.height, hr::limits::kImageSize);
  checkFlag("--threads", a.threads, hr::limits::kThreads);
  const bool walk = !a.walkthrough.empty();
  if (!walk && !a.frames.empty()) throw hr::InputError("--frames: only with --walkthrough PATH.json");
  if (!walk && !a.video.empty()) throw hr::InputError("--video: only with --walkthrough PATH.json");
  if (!walk && a.benchmark) throw hr::InputError("--benchmark: only with --walkthrough PATH.json");
  if (walk && a.frames.empty() && a.video.empty())
    throw hr::InputError("--walkthrough: give --frames DIR and/or --video OUT.mp4 for the replay");
  if (a.benchmark && a.frames.empty()) throw hr::InputError("--benchmark: give --frames DIR (timings.csv and summary.json go there)");
  if (!a.video.empty() && fs::path(a.video).extension() != ".mp4") throw hr::InputError("--video: the file must end in .mp4");
  if (fs::path(a.record).extension() != ".json") throw hr::InputError("--record: the camera path file must end in .json");
  std::error_code ec;
  if (!fs::is_directory(a.screenshotDir, ec)) throw hr::InputError("--screenshot-dir: " + a.screenshotDir + " is not a folder");
  fs::path recordDir = fs::absolute(a.record, ec).parent_path();
  if (!fs::is_directory(recordDir, ec)) throw hr::InputError("--record: " + recordDir.string() + " is not a folder");
}

}  // namespace

void addViewOptions(CLI::App* v, ViewArgs& a) {
  v->add_option("solution", a.solution, "solution.ghrs")->required();
  v->add_option("--camera", a.camera, "start camera (default: the first); its still's exposure is the session's");
  v->add_option("--angle-threshold", a.angleThreshold,
                "re-evaluate a glossy vertex only when its view direction turned by more than this, degrees (default 0: every frame)");
  v->add_option("--exposure", a.exposure, "exposure instead of the start camera's still's (radiance 1/E maps to 0.18)");
  v->add_option("--width", a.width, "window or frame width, pixels (default: the camera's or path's)");
  v->add_option("--height", a.height, "window or frame height, pixels");
  v->add_option("--threads", a.threads, "threads for the glossy update (default: all cores)");
  v->add_option("--walkthrough", a.walkthrough, "camera path (.json) to replay headless");
  v->add_option("--frames", a.frames, "with --walkthrough: folder for the numbered PNG frames");
  v->add_option("--video", a.video, "with --walkthrough: encode the frames to this .mp4 (needs ffmpeg)");
  v->add_flag("--benchmark", a.benchmark, "with --walkthrough and --frames: per-frame timings (timings.csv) and a summary");
  v->add_flag("--diffuse-only", a.diffuseOnly, "start with the diffuse-only display (g toggles)");
  v->add_option("--record", a.record, "where r writes the recorded camera path")->capture_default_str();
  v->add_option("--screenshot-dir", a.screenshotDir, "where screenshots go")->capture_default_str();
  v->add_flag("--quiet", a.quiet, "no progress on stderr");
}

int runView(const ViewArgs& a) {
  checkFlags(a);
  hr::Solution sol = hr::loadSolution(a.solution);
  hr::SolutionView host(sol);
  std::unique_ptr<hr::Extension> ext = loadExtension(sol, host, a.solution);
  hr::Camera start = startCamera(a, sol);
  std::optional<view::CameraPath> path;
  if (!a.walkthrough.empty()) path = view::loadCameraPath(a.walkthrough);
  int threads = a.threads ? *a.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  try {
    const double exposure = a.exposure ? *a.exposure : view::stillExposure(sol, ext.get(), start);
    view::SceneView scene(sol, ext.get(), exposure);
    scene.setThresholdDeg(a.angleThreshold.value_or(0.0));
    scene.showGlossy(!a.diffuseOnly);
    if (path) {
      int w = a.width ? *a.width : path->width > 0 ? path->width : start.width;
      int h = a.height ? *a.height : path->height > 0 ? path->height : start.height;
      view::WalkthroughOptions o{a.frames, a.video, a.benchmark, a.quiet};
      auto timings = view::runWalkthrough(scene, *path, w, h, o);
      if (!a.quiet) std::fprintf(stderr, "replayed %zu frames of %s (exposure %.6g)\n", timings.size(), a.walkthrough.c_str(), exposure);
      return 0;
    }
    view::requireDisplay();
    view::ViewerOptions o;
    o.cameras = sol.cameras;
    for (std::size_t i = 0; i < sol.cameras.size(); ++i)
      if (sol.cameras[i].name == start.name) o.startCamera = int(i);
    o.width = a.width.value_or(std::max(start.width, 960));
    o.height = a.height.value_or(o.width * start.height / std::max(start.width, 1));
    o.recordPath = a.record;
    o.screenshotDir = a.screenshotDir;
    view::Viewer viewer(scene, o);
    viewer.run();
    return 0;
  } catch (const view::EnvironmentError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
