// Threshold continuation under a memory budget. The memory a threshold costs above the fixed part
// is modelled as V(eps) = V_k (eps_k / eps)^alpha, alpha fitted to the last two passes (links and
// elements of hierarchical radiosity grow roughly as 1/eps; the fit absorbs each scene's own rate).
// The next threshold is the one the model says fills the budget, never more than a factor 2 below
// the last (the model is a local fit) and never below the requested eps. The law cannot foresee a
// jump in link count (the Cornell box's links grow by half between eps 6e-5 and 4e-5: the law said
// 100 MB and the pass peaked at 111-117), so the pass it chose is also capped from within: the
// memory per link the last pass cost, times the links refinement is about to make (RefineCap).
#include "memory_budget.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hr::detail {

namespace {
/// The coarsest threshold a budgeted solve starts from (in units of the emitted power, like eps).
constexpr double kStartEps = 1e-2;
/// The share of the budget the solve aims at. The law's step aims at all of it: a step the law gets
/// wrong is cut short by the cap, and a margin would only leave memory unspent.
constexpr double kAim = 1.0;
/// What writing the outputs (solution copy, .vtp, images' display structures) needs on top of the
/// memory in use when the solve ends, per element: measured 0.9-1.0 kB on the Soda Shoppe (55-64k
/// elements: 50-55 MB). The allocator reuses what the solve freed and still holds (free heap inside
/// the resident set), so the peak is the larger of the solve's own and the resident memory plus
/// what of this the free heap cannot hold.
constexpr double kOutputBytesPerElement = 1000.0;
/// The same for an extension's data, per byte it holds: measured 2.5 on the glossy Cornell box
/// (--dir-eps 0.05 --dir-max-level 5 at 80 MB: 79 MB beyond the per-element part for 31.7 MB of
/// distributions: the solution file's section is built in memory, and the display reads them).
constexpr double kOutputBytesPerExtensionByte = 2.5;
/// What one more directional level multiplies an extension's bytes by, until a raise is seen: a
/// level quarters the cells it refines, and the sums above them refine too (measured 4.8 on the
/// glossy Cornell box, levels 3 -> 4 at --dir-eps 0.05).
constexpr double kLevelGrowth = 5.0;
/// A step that would lower the threshold by less than this factor is not worth a pass: freeze.
constexpr double kMinStep = 0.95;
constexpr double kMaxStep = 0.5;
}  // namespace

std::vector<std::uint8_t> fitMostUrgent(const RefineCap& cap, std::size_t links, std::size_t elements,
                                        std::span<const double> urgency, std::span<const std::uint32_t> addLinks,
                                        std::span<const std::uint32_t> newLeaf, std::size_t newPerLeaf) {
  std::vector<std::uint32_t> order(urgency.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return urgency[a] > urgency[b]; });
  std::vector<std::uint8_t> take(urgency.size(), 0), split(elements, 0);
  for (std::uint32_t i : order) {
    const bool fresh = newLeaf[i] != kNoLeaf && !split[newLeaf[i]];
    const std::size_t l = links + addLinks[i], e = elements + (fresh ? newPerLeaf : 0);
    // A split that does not fit is skipped, not the end: a cheaper, less urgent one may still fit.
    if (!cap.fits(l, e)) continue;
    take[i] = 1, links = l, elements = e;
    if (fresh) split[newLeaf[i]] = 1;
  }
  return take;
}

MemoryBudget::MemoryBudget(std::size_t budgetBytes, double requestedEps)
    : budget_(budgetBytes),
      requested_(requestedEps),
      eps_(budgetBytes > 0 ? std::max(requestedEps, kStartEps) : requestedEps),
      levelGrowth_(kLevelGrowth) {}

void MemoryBudget::start(std::size_t baseRss) {
  base_ = baseRss;
  if (active() && double(baseRss) >= kAim * double(budget_)) frozen_ = exceeded_ = true;
}

int MemoryBudget::directionalLevels() const {
  if (!active()) return -1;
  return std::min(dirCeiling_, 1 + int(std::floor(std::log(kStartEps / eps_) / std::log(4.0) + 1e-9)));
}

void MemoryBudget::afterPass(std::size_t peakRss, std::size_t rss, std::size_t freeHeap, std::size_t elements,
                             std::size_t links, bool cut, std::size_t extensionBytes) {
  steppedBack_ = false;
  if (!active()) return;
  const double room = kAim * double(budget_) - double(base_);
  const double outputs = std::max(
      0.0, kOutputBytesPerElement * double(elements) + kOutputBytesPerExtensionByte * double(extensionBytes) - double(freeHeap));
  const double atEnd = std::max(double(peakRss), double(rss) + outputs);
  const double var = std::max(1.0, atEnd - double(base_));
  // Directional detail is the one thing a budget can take back: the distributions are rebuilt every
  // sweep. A pass whose outputs would overrun with them steps one level back (and never up again).
  const int used = directionalLevels();
  const double ext = double(extensionBytes);
  if (used > lastLevels_ && lastLevels_ >= 0 && lastExtension_ > 0.0)
    levelGrowth_ = std::max(levelGrowth_, ext / lastExtension_);
  lastLevels_ = used, lastExtension_ = ext;
  if (var >= room && ext > 0.0 && used > 0) {
    dirCeiling_ = used - 1, steppedBack_ = true;
    return;  // the next pass measures again with the memory given back
  }
  // A level more multiplies what the distributions hold (and what writing them out costs) within one
  // sweep, where no cap can stop it: it is taken only if that fits.
  if (ext > 0.0 && var + (levelGrowth_ - 1.0) * (1.0 + kOutputBytesPerExtensionByte) * ext > room)
    dirCeiling_ = std::min(dirCeiling_, used);
  if (frozen_) return;
  // The cap for the next pass: this pass's memory per link, the outputs' share per element apart
  // (they grow with elements, not links); never less than half of the whole per link, so a pass
  // whose outputs estimate dwarfs its links does not make links look free.
  const double perElement = kOutputBytesPerElement;
  const double linkShare = std::max(var - perElement * double(elements), 0.5 * var);
  cap_ = {links > 0 ? linkShare / double(links) : 0.0, perElement, room};
  if (var >= room || cut) {
    frozen_ = true;  // full, or the cap already spent the rest of the budget within this pass
    exceeded_ = var >= room && lastEps_ == 0.0;  // the coarsest pass alone did not fit
    return;
  }
  if (atRequested()) {
    lastEps_ = eps_, lastVar_ = var;
    return;  // refinement continues at the requested eps, as without a budget, until it would not fit
  }
  double alpha = 1.0;
  if (lastEps_ > eps_ && lastVar_ > 0.0 && var > lastVar_)
    alpha = std::clamp(std::log(var / lastVar_) / std::log(lastEps_ / eps_), 0.3, 3.0);
  const double next = eps_ * std::pow(var / room, 1.0 / alpha);
  lastEps_ = eps_, lastVar_ = var;
  const double clamped = std::max({next, eps_ * kMaxStep, requested_});
  if (clamped > eps_ * kMinStep) {
    frozen_ = true;  // the budget is (nearly) full at this threshold
    return;
  }
  eps_ = clamped;
}

}  // namespace hr::detail
