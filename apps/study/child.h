// Runs glossyhr itself as a child process: a study solves each configuration in a process of its own,
// so that the peak memory it reports is that configuration's alone and a crash is one row's failure.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace study {

/// A private folder for child runs' outputs, <temp>/glossyhr-<what>-<pid>, removed with everything
/// in it when it goes out of scope (the commands keep only what they copy into their output set).
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& what);
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

struct ChildResult {
  int exitCode = -1;   // the child's exit code, or 128 + signal when it was killed by one
  double seconds = 0;  // wall time, process start to exit
};

/// Runs `program` (searched on PATH when it has no slash) with `args`, stdout and stderr appended to
/// `logPath`. Throws std::runtime_error when the process cannot be started.
/// `image`, when given, is the file executed (argv[0] stays `program`).
ChildResult run(const std::string& program, const std::vector<std::string>& args, const std::string& logPath,
                const std::string& image = "");
/// run() of this executable: the one running, even if a rebuild has since replaced or deleted its file
/// (a study of the Soda Shoppe lasts an hour; every configuration must be solved by the same build).
ChildResult runSelf(const std::vector<std::string>& args, const std::string& logPath);

/// Why a child failed: the first line of `logPath` that starts with "error", else its first line
/// that is not a warning or a note.
std::string failureReason(const std::string& logPath);

}  // namespace study
