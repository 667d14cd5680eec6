// Helpers the glossy benches share: reading a scene file, an extension's statistic by name, the
// emitting objects (left out of image comparisons: their pixels copy the scene's emission), and
// running one solve in a forked process so that its peak RSS is its own.
#pragma once
#include <hr/scene.h>
#include <hr/solver.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

namespace bench {

inline std::string readFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

inline double stat(const std::vector<hr::StatEntry>& s, const char* name) {
  for (const auto& e : s)
    if (e.name == name) return e.value;
  return 0.0;
}

/// The common command line: [SOURCE_DIR] [--quick] (other flags are the bench's own).
/// `more`: the bench's other flags, which it reads itself. Any other flag (a typo, --help) stops
/// with exit 2 rather than starting the bench's full, half-hour run as if it were not there.
inline void sourceAndQuick(int argc, char** argv, std::string& src, bool& quick,
                           std::initializer_list<const char*> more = {}) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      quick = true;
    } else if (a.rfind("--", 0) != 0) {
      src = a;
    } else if (std::find(more.begin(), more.end(), a) == more.end()) {
      std::string valid = "--quick";
      for (const char* m : more) valid += std::string(", ") + m;
      std::fprintf(stderr, "%s: unknown option '%s' (valid: %s, and a source directory)\n", argv[0], a.c_str(),
                   valid.c_str());
      std::exit(2);
    }
  }
}

/// Runs `run` (returning a trivially copyable Row with `ok`, `peakRssMB` and `cpuSeconds`) in a
/// child process; the Row comes back through a pipe with the child's peak RSS and CPU time (user +
/// system) filled in.
template <class Row, class F>
Row forked(F&& run) {
  int fd[2];
  if (pipe(fd) != 0) return {};
  pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    Row r = run();
    ssize_t w = write(fd[1], &r, sizeof r);
    _exit(w == ssize_t(sizeof r) ? 0 : 1);
  }
  close(fd[1]);
  Row r;
  ssize_t got = read(fd[0], &r, sizeof r);
  close(fd[0]);
  int status = 0;
  rusage ru{};
  wait4(pid, &status, 0, &ru);
  if (got != ssize_t(sizeof r) || !WIFEXITED(status) || WEXITSTATUS(status) != 0) r.ok = false;
  r.peakRssMB = double(ru.ru_maxrss) / 1024.0;
  r.cpuSeconds = double(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) + 1e-6 * double(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
  return r;
}

}  // namespace bench
