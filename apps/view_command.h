// `glossyhr view`: a saved solution in a VTK window (interactive, see view/viewer.h) or, with
// --walkthrough, a camera path rendered headless to PNG frames, a video and frame timings (see
// view/walkthrough.h). Every flag is checked before a window opens; bad input exits 2.
#pragma once
#include <CLI/CLI.hpp>

#include <optional>
#include <string>

struct ViewArgs {
  std::string solution, camera, walkthrough, frames, video, record = "camera_path.json", screenshotDir = ".";
  std::optional<double> angleThreshold, exposure;
  std::optional<int> width, height, threads;
  bool benchmark = false, diffuseOnly = false, quiet = false;
};

/// Adds the subcommand's options to `view`.
void addViewOptions(CLI::App* view, ViewArgs& a);
int runView(const ViewArgs& a);
