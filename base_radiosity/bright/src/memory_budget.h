// A memory budget that steers refinement (--memory-mb): the solve starts coarse and lowers its
// threshold pass by pass, as far as the budget allows, instead of refining once at the requested
// eps and finding out afterwards what that cost. The oracle already ranks links by their error, so
// each lower threshold spends the next memory where the error is largest (the paper's §7 wish:
// savings in memory at the cost of visual quality, under the user's control). Between passes the
// threshold is predicted from a fitted law; within a pass a cap (RefineCap) stops refinement when
// the links and elements it is about to make would not fit, since a fitted law cannot see a jump in
// link count coming.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace hr::detail {

/// What a refinement pass may hold: the memory above the fixed part is modelled as perLink bytes per
/// link plus perElement per element, perLink measured on the previous pass (its peak, transients and
/// outputs included). Inactive (perLink 0) until a pass has been measured.
struct RefineCap {
  double perLink = 0.0, perElement = 0.0, room = 0.0;
  bool active() const { return perLink > 0.0; }
  bool fits(std::size_t links, std::size_t elements) const {
    return !active() || perLink * double(links) + perElement * double(elements) <= room;
  }
  /// The most links that fit beside `elements` elements (any number when inactive).
  std::size_t maxLinks(std::size_t elements) const {
    if (!active()) return ~std::size_t(0);
    return std::size_t(std::max(0.0, room - perElement * double(elements)) / perLink);
  }
};

/// Which of some optional splits a capped refinement round makes: the most urgent first (ties in
/// their order), each while the cap still holds. `links` and `elements` are the counts if none is
/// made; split i adds addLinks[i] links and, if newLeaf[i] (an element id below `elements`, or
/// kNoLeaf) is not yet split by an accepted one, newPerLeaf elements.
constexpr std::uint32_t kNoLeaf = 0xffffffffu;
std::vector<std::uint8_t> fitMostUrgent(const RefineCap& cap, std::size_t links, std::size_t elements,
                                        std::span<const double> urgency, std::span<const std::uint32_t> addLinks,
                                        std::span<const std::uint32_t> newLeaf, std::size_t newPerLeaf);

class MemoryBudget {
 public:
  /// budgetBytes 0: no budget (the threshold is the requested eps from the first pass on).
  MemoryBudget(std::size_t budgetBytes, double requestedEps);
  bool active() const { return budget_ > 0; }
  /// The threshold the next pass refines with; frozen(): the next pass does not refine at all.
  double eps() const { return eps_; }
  bool frozen() const { return frozen_; }
  /// Whether the threshold has come down to the requested eps (a converged solve needs it, or a
  /// budget that froze refinement first).
  bool atRequested() const { return eps_ <= requested_; }
  /// Levels of directional subdivision above the coarsest the next pass may use, or -1: any (no
  /// budget). One per factor 4 the threshold has come down from the start (as a spatial level
  /// quarters an element's area), raised one at a time in a pass that does not refine further, and
  /// only while a level more fits, together with the threshold a factor 4 further down.
  int directionalLevels() const;
  /// Whether the last afterPass lowered the directional levels (the next pass must sweep with them:
  /// the distributions are rebuilt every sweep, so a lower level gives their memory back).
  bool directionsSteppedBack() const { return steppedBack_; }
  /// The cap the next pass's refinement must keep.
  const RefineCap& cap() const { return cap_; }
  /// Before the first pass: the peak resident memory of what the solve holds whatever the
  /// threshold (scene, hierarchy of patches, visibility structure), bytes.
  void start(std::size_t baseRss);
  /// After a pass's sweeps, with the peak and current resident memory, the free heap the allocator
  /// holds inside it (bytes), the element and link counts, whether the cap cut the pass short, and
  /// the bytes an extension holds (Extension::heldBytes):
  /// chooses the next threshold from the memory each threshold has cost, outputs included (a power
  /// law fitted to the last two passes), or freezes.
  void afterPass(std::size_t peakRss, std::size_t rss, std::size_t freeHeap, std::size_t elements,
                 std::size_t links, bool cut, std::size_t extensionBytes = 0);
  /// The budget could not hold even the coarsest pass.
  bool exceeded() const { return exceeded_; }

 private:
  std::size_t budget_;
  double requested_, eps_;
  bool frozen_ = false, exceeded_ = false;
  std::size_t base_ = 0;
  double lastEps_ = 0.0, lastVar_ = 0.0;  // the previous pass: threshold and memory above the base
  RefineCap cap_;
  /// One level of directional subdivision per factor 4 the threshold has come down from the start.
  static int levelsFor(double eps);
  int levels_ = 1;            // the directional levels the next pass uses
  int dirCeiling_ = 1 << 20;  // directional levels are held at or below this once they would not fit
  std::size_t lastLinks_ = 0; // the links after the previous pass
  double restPerLink_ = 0.0;  // the cap's price per link beside the extension's bytes, last pass
  bool steppedBack_ = false;
  int lastLevels_ = -1;          // the directional levels the previous pass used, and the extension's
  double lastExtension_ = 0.0;   // bytes then
  double levelGrowth_;           // the extension's bytes per level raised: kLevelGrowth or more, as seen
};

}  // namespace hr::detail
