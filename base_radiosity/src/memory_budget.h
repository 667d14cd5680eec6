// A memory budget that steers refinement (--memory-mb): the solve starts coarse and lowers its
// threshold pass by pass, as far as the budget allows, instead of refining once at the requested
// eps and finding out afterwards what that cost. The oracle already ranks links by their error, so
// each lower threshold spends the next memory where the error is largest (the paper's §7 wish:
// savings in memory at the cost of visual quality, under the user's control).
#pragma once
#include <cstddef>

namespace hr::detail {

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
  /// Before the first pass: the peak resident memory of what the solve holds whatever the
  /// threshold (scene, hierarchy of patches, visibility structure), bytes.
  void start(std::size_t baseRss);
  /// After a pass's sweeps, with the peak and current resident memory, the free heap the
  /// allocator holds inside it (bytes) and the element count: chooses the next threshold from the memory each threshold has cost, outputs included
  /// (a power law fitted to the last two passes), or freezes.
  void afterPass(std::size_t peakRss, std::size_t rss, std::size_t freeHeap, std::size_t elements);
  /// The budget could not hold even the coarsest pass.
  bool exceeded() const { return exceeded_; }

 private:
  std::size_t budget_;
  double requested_, eps_;
  bool frozen_ = false, exceeded_ = false;
  std::size_t base_ = 0;
  double lastEps_ = 0.0, lastVar_ = 0.0;  // the previous pass: threshold and memory above the base
};

}  // namespace hr::detail
