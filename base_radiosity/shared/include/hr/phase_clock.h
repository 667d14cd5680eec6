// Phase timing for stats.json, the same on every host: the wall and CPU seconds a phase took and
// the distinct worker threads that did some of its work (a phase that should be parallel but ran
// on one thread shows in stats.json, and fails a test).
#pragma once
#include <atomic>
#include <chrono>
#include <cstdint>

namespace hr {

/// CPU seconds of the whole process (all threads).
double processCpuSeconds();

/// Marks the calling TBB worker (its arena index, modulo 64) in a phase's mask: call from inside
/// the phase's parallel bodies.
void markThread(std::atomic<std::uint64_t>& mask);
/// How many distinct workers a mask has seen.
int threadCount(const std::atomic<std::uint64_t>& mask);

/// Adds the wall and CPU seconds of its own lifetime to c.wall and c.cpu: c is a PhaseStat or a
/// host's phase clock.
class PhaseTimer {
 public:
  template <class Clock>
  explicit PhaseTimer(Clock& c) : wall_(c.wall), cpu_(c.cpu) {}
  ~PhaseTimer();
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

 private:
  double& wall_;
  double& cpu_;
  std::chrono::steady_clock::time_point w0_ = std::chrono::steady_clock::now();
  double c0_ = processCpuSeconds();
};

}  // namespace hr
