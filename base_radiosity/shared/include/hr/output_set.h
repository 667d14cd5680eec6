// Outputs as a set. Every file of a run (solution, images, stats) is written into a staging folder
// inside the output folder, ".ghr-staging-<pid>", and moved into place only when all of them are
// complete: first a COMMIT list is written (atomically) into the staging folder, then each file is
// renamed over its target. A run that fails before COMMIT leaves the folder as it was (its staging
// folder is removed); a run killed at any moment leaves a staging folder that the next run writing to
// the same folder finishes (COMMIT present: the renames are completed, so the new set is whole) or
// removes (no COMMIT: the previous files were never touched). Commit and recovery hold an flock on
// the output folder, so concurrent runs do not interleave their renames.
#pragma once
#include <string>
#include <vector>

namespace hr {

class OutputSet {
 public:
  /// Checks, before anything is written: dir is a directory or can be created, and no target name
  /// is taken by something other than a regular file (a directory named stats.json would make the
  /// set impossible to complete). Finishes or removes stale staging folders in dir. Names are plain
  /// file names. Throws InputError naming the flag (flag, e.g. "-o") and the path.
  OutputSet(std::string dir, std::vector<std::string> names, std::string flag = "-o");
  ~OutputSet();
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  /// The path to write name to (inside the staging folder, created on first use).
  std::string path(const std::string& name);
  /// Moves every file into place; each name must have been written.
  void commit();
  /// The final paths, in the order of names.
  std::vector<std::string> finalPaths() const;

 private:
  std::string dir_, staging_, flag_;
  std::vector<std::string> names_;
  bool committed_ = false;
};

/// Finishes or removes the staging folders of runs that are no longer alive (see above). Called by
/// OutputSet's constructor; exposed for tests and tools.
void recoverOutputs(const std::string& dir);

}  // namespace hr
