// Progress reporting on stderr. Lines, not carriage returns, when stderr is not a terminal (CI logs).
#include <hr/progress.h>
#include <unistd.h>

#include <cstdio>

namespace hr {

Progress::Progress(bool quiet) : quiet_(quiet), start_(std::chrono::steady_clock::now()), last_(start_) {}

double Progress::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::phase(const std::string& name) {
  phase_ = name;
  if (!quiet_) std::fprintf(stderr, "[%7.2fs] %s\n", elapsed(), name.c_str());
}

void Progress::update(double f) {
  if (quiet_) return;
  auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - last_).count() < (isatty(2) ? 0.2 : 5.0)) return;
  last_ = now;
  std::fprintf(stderr, isatty(2) ? "\r[%7.2fs] %s %5.1f%%" : "[%7.2fs] %s %5.1f%%\n", elapsed(), phase_.c_str(),
               100.0 * f);
  std::fflush(stderr);
}

void Progress::note(const std::string& line) {
  if (!quiet_) std::fprintf(stderr, "%s[%7.2fs] %s\n", isatty(2) ? "\r" : "", elapsed(), line.c_str());
}

}  // namespace hr
