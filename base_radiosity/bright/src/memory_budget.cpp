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
/// What writing the outputs (the .ghrs and .vtp streamed, the images' display structures) needs on
/// top of the memory in use when the solve ends, per element and per byte an extension holds. Measured
/// (RSS sampled every 20 ms; 2026-12-03, after the solution file and the extension's section were
/// streamed): 3.4 MB for the diffuse Soda Shoppe's 39k elements (87 bytes each), 3.5 MB for the
/// glossy Cornell box's 6.2k elements and 48 MB of distributions (0.06 per byte); about twice those
/// here. Before the streaming they were 1 kB per element and 2.5 bytes per byte (the section was
/// built in memory), and the budget left a third of itself unspent. The allocator reuses what the
/// solve freed and still holds (free heap inside the resident set), so the peak is the larger of the
/// solve's own and the resident memory plus what of this the free heap cannot hold.
constexpr double kOutputBytesPerElement = 200.0;
constexpr double kOutputBytesPerExtensionByte = 0.15;
/// What one more directional level multiplies an extension's bytes by, until a raise is seen: a
/// level quarters the cells it refines, and the sums above them refine too (measured 4.8 on the
/// glossy Cornell box, levels 3 -> 4 at --dir-eps 0.05).
constexpr double kLevelGrowth = 5.0;
/// A step that would lower the threshold by less than this factor is not worth a pass: freeze.
constexpr double kMinStep = 0.95;
constexpr double kMaxStep = 0.5;
/// How far below the threshold where a directional level begins the budget must let the threshold go
/// for the level to be taken: two spatial levels' worth (a factor 4 each). One (a factor 4) was not
/// enough on the glossy Cornell box: 200 MB took level 4 and reached eps 9.3e-5 (image 2.56 % from a
/// fine solve), where 150 MB kept level 3 and reached 7.8e-5 (2.32 %); a Haar level multiplies the
/// distributions' memory by about 5, a spatial level the links' by about 4, and near these
/// thresholds the image's error follows the spatial one.
constexpr double kLevelReach = 16.0;
/// A pass cut short below this share of the room refines again at its threshold (see afterPass).
constexpr double kRefill = 0.95;
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

int MemoryBudget::levelsFor(double eps) { return 1 + int(std::floor(std::log(kStartEps / eps) / std::log(4.0) + 1e-9)); }

int MemoryBudget::directionalLevels() const { return active() ? levels_ : -1; }

void MemoryBudget::afterPass(std::size_t peakRss, std::size_t rss, std::size_t freeHeap, std::size_t elements,
                             std::size_t links, bool cut, std::size_t extensionBytes) {
  steppedBack_ = false;
  if (!active()) return;
  const double room = kAim * double(budget_) - double(base_);
  const double outputs = std::max(
      0.0, kOutputBytesPerElement * double(elements) + kOutputBytesPerExtensionByte * double(extensionBytes) - double(freeHeap));
  const double atEnd = std::max(double(peakRss), double(rss) + outputs);
  const double var = std::max(1.0, atEnd - double(base_));
  // The law's exponent, fitted to this pass and the last (1 until two passes are seen).
  double alpha = 1.0;
  if (lastEps_ > eps_ && lastVar_ > 0.0 && var > lastVar_)
    alpha = std::clamp(std::log(var / lastVar_) / std::log(lastEps_ / eps_), 0.3, 3.0);
  // Directional detail is the one thing a budget can take back: the distributions are rebuilt every
  // sweep. A pass after which the memory in use and the outputs would overrun steps one level back
  // (and never up again). Not for a peak already past: it is a high-water mark, and read so it
  // stepped a 400 MB solve back pass after pass down to level 1 for one overrun long past, and a
  // 100 MB one to level 1 for a peak 5 % over (image error 0.060 against 0.031 at level 3).
  const int used = levels_;
  const double ext = double(extensionBytes);
  if (used > lastLevels_ && lastLevels_ >= 0 && lastExtension_ > 0.0)
    levelGrowth_ = std::max(levelGrowth_, ext / lastExtension_);
  lastLevels_ = used, lastExtension_ = ext;
  if (double(rss) + outputs >= kAim * double(budget_) && ext > 0.0 && used > 0) {
    dirCeiling_ = levels_ = used - 1, steppedBack_ = true;
    return;  // the next pass measures again with the memory given back
  }
  // A level more multiplies what the distributions hold (and what writing them out costs) within one
  // sweep, where no cap can stop it: it is taken only if that fits.
  const double grownNow = var + (levelGrowth_ - 1.0) * (1.0 + kOutputBytesPerExtensionByte) * ext;
  if (ext > 0.0 && grownNow > room) dirCeiling_ = std::min(dirCeiling_, used);
  // And it is worth taking only with the spatial detail that goes with it: the threshold kLevelReach
  // below where it begins, by the fitted law. Taken without, the budget then stopped spatial
  // refinement early and the error went up with the budget: the glossy Cornell box at 400 MB raised
  // to level 5 and stopped at eps 1.3e-4 (image 2.8 % from a fine solve), where 300 MB kept level 4
  // and reached 4.1e-5 (1.6 %). Judged anew every pass: the next one measures nearer the threshold
  // where the level begins.
  bool hold = false;
  if (ext > 0.0) {
    const double begins = kStartEps / std::pow(4.0, double(used));
    const double target = std::min(eps_, begins / kLevelReach);
    hold = grownNow * std::pow(eps_ / target, alpha) > room;
  }
  if (frozen_) return;
  // The cap for the next pass: this pass's memory per link, the outputs' share per element apart
  // (they grow with elements, not links); never less than half of the whole per link, so a pass
  // whose outputs estimate dwarfs its links does not make links look free.
  const double perElement = kOutputBytesPerElement;
  const double linkShare = std::max(var - perElement * double(elements), 0.5 * var);
  // Priced in two parts: the extension's bytes per link as they are now, and the rest. A pass that
  // made few links (a pass of its own for a directional level) did not hold its links twice as
  // refinement does, so its rest is too low a price for the next, refining pass: it keeps the last
  // refining pass's if that was higher. The glossy Cornell box at 400 MB priced the pass after its
  // level raise at 297 bytes a link (the whole of the raise pass), the pass cost 341 (the rest as
  // in the refining pass before, 207, and the extension's at the new level, 117-150) and peaked at 1.14 x.
  const double perLinkExt = links > 0 ? std::min(ext, linkShare) / double(links) : 0.0;
  double rest = links > 0 ? linkShare / double(links) - perLinkExt : 0.0;
  if (double(links) < 1.05 * double(lastLinks_)) rest = std::max(rest, restPerLink_);
  restPerLink_ = rest;
  cap_ = {links > 0 ? rest + perLinkExt : 0.0, perElement, room};
  // A pass the cap cut short but that ended well inside the budget refines again at its threshold,
  // under a cap measured on itself: the cost per link it prices by is the whole memory above the
  // base over the links, so the parts that do not grow with links (distributions of coarse nodes,
  // caches) make it too dear, and the glossy Cornell box at 250 MB stopped at 0.86 of its budget.
  // Only while such a pass still adds links, so refinement always ends.
  const bool grew = links > lastLinks_;
  lastLinks_ = links;
  if (cut && var < kRefill * room && grew) {
    lastEps_ = eps_, lastVar_ = var;
    return;
  }
  if (var >= room || cut) {
    frozen_ = true;  // full, or the cap already spent the rest of the budget within this pass
    exceeded_ = var >= room && lastEps_ == 0.0;  // the coarsest pass alone did not fit
    return;
  }
  // The level follows the threshold reached, one pass behind and in a pass of its own: the cap prices
  // a pass's links at the last pass's cost per link, which a level more changes (the glossy Cornell
  // box at 400 MB raised its level and lowered its threshold in one pass and peaked at 1.15 x).
  if (!hold && std::min(dirCeiling_, levelsFor(eps_)) > used) {
    levels_ = used + 1;
    lastEps_ = eps_, lastVar_ = var;
    return;
  }
  if (atRequested()) {
    lastEps_ = eps_, lastVar_ = var;
    return;  // refinement continues at the requested eps, as without a budget, until it would not fit
  }
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
