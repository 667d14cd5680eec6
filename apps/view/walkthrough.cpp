// Headless walkthroughs (see walkthrough.h).
#include "walkthrough.h"

#include <hr/output.h>
#include <hr/output_set.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "still.h"
#include "window.h"

namespace fs = std::filesystem;

namespace view {

namespace {

/// Removes a frames folder this run created if the run did not complete (an output set leaves the
/// folder it made, empty, when it never commits).
struct FolderGuard {
  fs::path dir;
  bool created = false, done = false;
  explicit FolderGuard(const std::string& d) : dir(d) { created = !d.empty() && !fs::exists(d); }
  ~FolderGuard() {
    std::error_code ec;
    if (created && !done) fs::remove(dir, ec);  // only when empty: never a user's files
  }
};

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

void encodeVideo(const std::string& ffmpeg, const std::string& framesDir, double fps, const std::string& video, bool quiet) {
  hr::writeAtomically(video, [&](const std::string& tmp) {
    std::ostringstream cmd;
    // yuv420p and even sizes: the H.264 stream every player opens.
    cmd << shellQuote(ffmpeg) << " -y -loglevel error -framerate " << fps << " -i "
        << shellQuote((fs::path(framesDir) / "frame_%05d.png").string())
        << " -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -pix_fmt yuv420p -f mp4 " << shellQuote(tmp);
    if (quiet) cmd << " 2>/dev/null";
    int rc = std::system(cmd.str().c_str());
    if (rc != 0) throw std::runtime_error("ffmpeg failed (status " + std::to_string(rc) + ") encoding " + video);
  });
}

}  // namespace

TimingSummary summarize(std::vector<double> ms) {
  TimingSummary s;
  if (ms.empty()) return s;
  std::sort(ms.begin(), ms.end());
  // Nearest rank: the smallest value with at least a fraction q of all values at or below it.
  auto at = [&](double q) { return ms[std::size_t(std::max(1.0, std::ceil(q * double(ms.size())))) - 1]; };
  s.median = ms.size() % 2 ? ms[ms.size() / 2] : 0.5 * (ms[ms.size() / 2 - 1] + ms[ms.size() / 2]);
  s.p95 = at(0.95);  // nearest rank
  s.max = ms.back();
  return s;
}

std::string frameName(int i) {
  char b[32];
  std::snprintf(b, sizeof b, "frame_%05d.png", i);
  return b;
}

std::string findFfmpeg() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string d; std::getline(dirs, d, ':');) {
    fs::path p = fs::path(d.empty() ? "." : d) / "ffmpeg";
    if (::access(p.c_str(), X_OK) == 0 && fs::is_regular_file(p)) return p.string();
  }
  return {};
}

std::vector<FrameTiming> runWalkthrough(SceneView& scene, const CameraPath& path, int width, int height,
                                        const WalkthroughOptions& opt) {
  const int n = path.frameCount();
  std::string ffmpeg;
  if (!opt.video.empty()) {
    if (fs::path(opt.video).extension() != ".mp4") throw hr::InputError("--video: the file must end in .mp4");
    ffmpeg = findFfmpeg();
    if (ffmpeg.empty())
      throw EnvironmentError("--video: ffmpeg is not installed (not found on PATH), so no video can be encoded; "
                             "install it (apt-get install ffmpeg) or write PNG frames with --frames DIR alone");
  }
  // Everything this run writes is announced first: a folder that cannot take it fails before frame 0.
  std::vector<std::string> names;
  const bool keepFrames = !opt.framesDir.empty();
  for (int i = 0; keepFrames && i < n; ++i) names.push_back(frameName(i));
  if (opt.benchmark) names.insert(names.end(), {"timings.csv", "summary.json"});
  FolderGuard guard(opt.framesDir);
  std::unique_ptr<hr::OutputSet> frames;
  if (keepFrames) frames = std::make_unique<hr::OutputSet>(opt.framesDir, names, "--frames");
  std::unique_ptr<hr::OutputSet> videoSet;
  if (!opt.video.empty())
    videoSet = std::make_unique<hr::OutputSet>(fs::path(opt.video).parent_path().string(),
                                               std::vector<std::string>{fs::path(opt.video).filename().string()}, "--video");
  // A video without kept frames encodes from a scratch folder that goes away afterwards.
  fs::path scratch;
  if (!opt.video.empty() && !keepFrames) {
    scratch = fs::temp_directory_path() / ("ghr_view_frames_" + std::to_string(::getpid()));
    fs::create_directories(scratch);
  }
  struct ScratchGuard {
    fs::path p;
    ~ScratchGuard() {
      std::error_code ec;
      if (!p.empty()) fs::remove_all(p, ec);
    }
  } scratchGuard{scratch};

  requireDisplay();
  // Timed frames are drawn as the window draws them (multisampled, width x height); other frames are
  // stills of 3 x 3 samples per pixel averaged in radiance, as `glossyhr render` draws them.
  const int k = opt.benchmark ? 1 : kStillSamples;
  auto win = makeWindow(width * k, height * k, true);
  if (k > 1) win->SetMultiSamples(0);
  win->AddRenderer(scene.renderer());
  std::vector<FrameTiming> timings;
  for (int i = 0; i < n; ++i) {
    auto t0 = std::chrono::steady_clock::now();
    scene.setCamera(cameraAt(path, path.frameTime(i), width, height));
    FrameStats st = scene.updateGlossy();
    win->Render();
    win->WaitForCompletion();
    double total = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    timings.push_back({total, st.glossyMs, st.verticesUpdated});
    if (keepFrames || !scratch.empty()) {
      std::string file = keepFrames ? frames->path(frameName(i)) : (scratch / frameName(i)).string();
      std::vector<unsigned char> rgb = grabFrame(win);
      if (k > 1) rgb = downsampleStill(rgb, width, height, k, scene.exposure());
      hr::writePng8(rgb, width, height, file);
    }
    if (!opt.quiet && (i + 1) % 50 == 0) std::fprintf(stderr, "frame %d of %d\n", i + 1, n);
  }
  win->RemoveRenderer(scene.renderer());
  win->Finalize();
  if (opt.benchmark) {
    std::ostringstream csv;
    csv << "frame,total_ms,glossy_update_ms,vertices_updated\n";
    std::vector<double> total, glossy;
    for (std::size_t i = 0; i < timings.size(); ++i) {
      csv << i << "," << timings[i].totalMs << "," << timings[i].glossyMs << "," << timings[i].verticesUpdated << "\n";
      total.push_back(timings[i].totalMs);
      glossy.push_back(timings[i].glossyMs);
    }
    TimingSummary a = summarize(total), g = summarize(glossy);
    std::ostringstream js;
    js << "{\n  \"frames\": " << timings.size() << ",\n  \"glossy_vertices\": " << scene.glossyVertexCount()
       << ",\n  \"angle_threshold_deg\": " << scene.thresholdDeg() << ",\n  \"total_ms\": {\"median\": " << a.median
       << ", \"p95\": " << a.p95 << ", \"max\": " << a.max << "},\n  \"glossy_update_ms\": {\"median\": " << g.median
       << ", \"p95\": " << g.p95 << ", \"max\": " << g.max << "}\n}\n";
    hr::writeFileAtomically(frames->path("timings.csv"), csv.str());
    hr::writeFileAtomically(frames->path("summary.json"), js.str());
    std::printf("%d frames, %zu glossy vertices, threshold %g deg\n", n, scene.glossyVertexCount(), scene.thresholdDeg());
    std::printf("  frame time (ms):         median %.3f, 95th percentile %.3f, max %.3f\n", a.median, a.p95, a.max);
    std::printf("  glossy update (ms):      median %.3f, 95th percentile %.3f, max %.3f\n", g.median, g.p95, g.max);
  }
  if (frames) frames->commit();
  guard.done = true;
  if (!opt.video.empty()) {
    std::string from = keepFrames ? opt.framesDir : scratch.string();
    encodeVideo(ffmpeg, from, path.fps, videoSet->path(fs::path(opt.video).filename().string()), opt.quiet);
    videoSet->commit();
  }
  return timings;
}

}  // namespace view
