// Threshold continuation under a memory budget. The memory a threshold costs above the fixed part
// is modelled as V(eps) = V_k (eps_k / eps)^alpha, alpha fitted to the last two passes (links and
// elements of hierarchical radiosity grow roughly as 1/eps; the fit absorbs each scene's own rate).
// The next threshold is the one the model says fills the budget, never more than a factor 2 below
// the last (the model is a local fit) and never below the requested eps.
#include "memory_budget.h"

#include <algorithm>
#include <cmath>

namespace hr::detail {

namespace {
/// The coarsest threshold a budgeted solve starts from (in units of the emitted power, like eps).
constexpr double kStartEps = 1e-2;
/// The share of the budget the solve aims at; the fitted power law is local, trusted for a factor 2
/// in eps with a margin.
constexpr double kAim = 1.0;
constexpr double kSafety = 1.1;
/// What writing the outputs (solution copy, .vtp, images' display structures) needs on top of the
/// memory in use when the solve ends, per element: measured 0.9-1.0 kB on the Soda Shoppe (55-64k
/// elements: 50-55 MB). The allocator reuses what the solve freed and still holds (free heap inside
/// the resident set), so the peak is the larger of the solve's own and the resident memory plus
/// what of this the free heap cannot hold.
constexpr double kOutputBytesPerElement = 1000.0;
/// A step that would lower the threshold by less than this factor is not worth a pass: freeze.
constexpr double kMinStep = 0.95;
constexpr double kMaxStep = 0.5;
}  // namespace

MemoryBudget::MemoryBudget(std::size_t budgetBytes, double requestedEps)
    : budget_(budgetBytes), requested_(requestedEps), eps_(budgetBytes > 0 ? std::max(requestedEps, kStartEps) : requestedEps) {}

void MemoryBudget::start(std::size_t baseRss) {
  base_ = baseRss;
  if (active() && double(baseRss) >= kAim * double(budget_)) frozen_ = exceeded_ = true;
}

void MemoryBudget::afterPass(std::size_t peakRss, std::size_t rss, std::size_t freeHeap, std::size_t elements) {
  if (!active() || frozen_) return;
  const double room = kAim * double(budget_) - double(base_);
  const double outputs = std::max(0.0, kOutputBytesPerElement * double(elements) - double(freeHeap));
  const double atEnd = std::max(double(peakRss), double(rss) + outputs);
  const double var = std::max(1.0, atEnd - double(base_));
  if (var >= room) {
    frozen_ = true;
    exceeded_ = lastEps_ == 0.0;  // the coarsest pass alone did not fit
    return;
  }
  if (atRequested()) {
    lastEps_ = eps_, lastVar_ = var;
    return;  // refinement continues at the requested eps, as without a budget, until it would not fit
  }
  double alpha = 1.0;
  if (lastEps_ > eps_ && lastVar_ > 0.0 && var > lastVar_)
    alpha = std::clamp(std::log(var / lastVar_) / std::log(lastEps_ / eps_), 0.3, 3.0);
  const double next = eps_ * std::pow(kSafety * var / room, 1.0 / alpha);
  lastEps_ = eps_, lastVar_ = var;
  const double clamped = std::max({next, eps_ * kMaxStep, requested_});
  if (clamped > eps_ * kMinStep) {
    frozen_ = true;  // the budget is (nearly) full at this threshold
    return;
  }
  eps_ = clamped;
}

}  // namespace hr::detail
