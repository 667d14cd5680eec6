// `glossyhr study`: what accuracy costs. Sweeps a grid of solve configurations, each in its own
// process, against one path-traced reference, beside the path tracer's own error-against-time curve;
// writes study.csv, study.json and log-log plots (apps/study/plot_study.py, matplotlib).
#pragma once
#include <optional>
#include <string>

struct StudyArgs {
  std::string scene, out = "out/study", grid, reference, cache;
  std::optional<int> referenceSpp, threads, views;
  bool quiet = false, noPlots = false;
};

/// The grid a study sweeps when --grid is not given: the diffuse core and Illumination Samples in
/// each basis, at three spatial thresholds.
extern const char* kDefaultStudyGrid;

int runStudy(const StudyArgs& a);
