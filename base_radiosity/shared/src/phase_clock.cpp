// Phase timing shared by the hosts (hr/phase_clock.h).
#include <hr/phase_clock.h>
#include <tbb/task_arena.h>
#include <time.h>

#include <bit>

namespace hr {

double processCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

void markThread(std::atomic<std::uint64_t>& mask) {
  int i = tbb::this_task_arena::current_thread_index();
  if (i >= 0) mask.fetch_or(std::uint64_t(1) << (i % 64), std::memory_order_relaxed);
}

int threadCount(const std::atomic<std::uint64_t>& mask) { return std::popcount(mask.load()); }

PhaseTimer::~PhaseTimer() {
  wall_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0_).count();
  cpu_ += processCpuSeconds() - c0_;
}

}  // namespace hr
