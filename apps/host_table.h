// The hosts `glossyhr solve --host NAME` can run, in an explicit table (no static-initializer
// registration: adding a host means adding a row in host_table.cpp). Each host turns a loaded scene
// into the host-independent hr::Solution and hr::SolveStats; everything after that (stats.json,
// images, solution.vtp, solution.ghrs) is written by the same code for every host.
#pragma once
#include <hr/extension.h>
#include <hr/progress.h>
#include <hr/solution.h>
#include <hr/solver.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

struct HostJob {
  hr::Scene& scene;
  const hr::SolverOptions& opt;
  std::unique_ptr<hr::Extension>& ext;  // the host may drop it when no material needs it
  const std::string& algorithm;
  hr::Progress& progress;
  bool quiet = false;
  /// Called once the cameras are known and before the solve: the caller opens the output folder
  /// there, so a bad -o fails before minutes of solving, not after.
  std::function<void()> ready;
};

struct HostResult {
  hr::Solution sol;
  hr::SolveStats st;
  /// The host's nodes and solver, kept until the outputs are written: the extension reads the host
  /// through them when it saves, renders and writes its part of the .vtp.
  std::shared_ptr<void> keep;
};

struct HostEntry {
  const char* name;
  const char* summary;
  const char* algorithms;  // the --algorithm values this host takes, for messages and --help
  const char* iterations;  // the --iteration values it takes, its default first ("gather, shoot")
  HostResult (*solve)(HostJob&);
  std::string defaultIteration() const { return std::string(iterations).substr(0, std::string(iterations).find(',')); }
  bool iterates(const std::string& scheme) const {
    const std::string list = std::string(", ") + iterations + ",";
    return list.find(" " + scheme + ",") != std::string::npos;
  }
};

const std::vector<HostEntry>& hostTable();
/// Looks a name up; throws hr::InputError listing the valid names when it is unknown.
const HostEntry& findHost(const std::string& name);
