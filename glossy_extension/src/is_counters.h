// Statistics of the Illumination Samples extension, updated by concurrent hooks: relaxed atomics
// (only their totals matter, and totals do not depend on the order of the updates).
#pragma once
#include <glossy/illumination_samples.h>
#include <glossy/reflection.h>

#include <atomic>
#include <cstdint>
#include <ctime>

namespace glossy {

struct IlluminationSamples::Counters {
  std::atomic<std::uint64_t> gatherCalls{0}, reflectCalls{0}, pullCalls{0};
  std::atomic<std::uint64_t> samplesReceived{0}, samplesKept{0}, samplesDropped{0}, samplesPeak{0};
  std::atomic<std::uint64_t> brdfEvaluations{0}, pullCells{0}, pullClips{0};
  std::atomic<std::uint64_t> lobesFromMemo{0}, lobesIntegrated{0}, sharedLayers{0};
  std::atomic<std::uint64_t> samplesSpread{0}, spreadLobes{0};
  std::atomic<std::uint64_t> reflectCpuNs{0}, pullCpuNs{0};

  static void raise(std::atomic<std::uint64_t>& a, std::uint64_t v) {
    std::uint64_t cur = a.load(std::memory_order_relaxed);
    while (cur < v && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
    }
  }
  static void add(std::atomic<std::uint64_t>& a, std::uint64_t v) { a.fetch_add(v, std::memory_order_relaxed); }
  /// What one reflection (or one layer of it) did.
  void add(const ReflectCounts& rc) {
    add(samplesReceived, rc.received);
    add(samplesKept, rc.kept);
    add(samplesDropped, rc.dropped);
    add(brdfEvaluations, rc.brdfEvaluations);
    add(lobesFromMemo, rc.lobesFromMemo);
    add(lobesIntegrated, rc.lobesIntegrated);
    add(samplesSpread, rc.spread);
    add(spreadLobes, rc.spreadLobes);
  }
};

/// CPU time of the calling thread, ns: summed over threads it is the work a phase cost.
inline std::uint64_t threadCpuNs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return std::uint64_t(t.tv_sec) * 1000000000ull + std::uint64_t(t.tv_nsec);
}

}  // namespace glossy
