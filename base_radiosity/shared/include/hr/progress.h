// Progress on stderr: phase, percentage and elapsed time, rate-limited; silent with --quiet.
#pragma once
#include <chrono>
#include <string>

namespace hr {

class Progress {
 public:
  explicit Progress(bool quiet = false);
  void phase(const std::string& name);
  void update(double fraction);  // 0..1 within the current phase
  void note(const std::string& line);  // a full line (e.g. per-iteration report)
  double elapsed() const;
  bool quiet() const { return quiet_; }

 private:
  bool quiet_;
  std::string phase_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace hr
