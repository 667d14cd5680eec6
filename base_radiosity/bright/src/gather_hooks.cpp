// The extension's link gather hook, called per receiver with the samples its links brought this
// iteration (or shooting pass). The calls walk the node tree top-down: parallel across disjoint
// subtrees, and a receiver only after every receiver above it has been called. That order is what
// lets an extension write the leaves below a receiver during gather (Radiance Clustering's immediate
// push) without locks, and always in the same order whatever the thread count.
#include <tbb/parallel_for.h>

#include "solver_state.h"

namespace hr::detail {
namespace {

class GatherHooks {
 public:
  explicit GatherHooks(SolverState& s) : s_(s), E_(s.h.elements().size()) {
    group_.assign(E_ + s.h.clusters().size(), kNone);
    for (std::uint32_t g = 0; g + 1 < s.groupStart.size(); ++g) group_[key(s.links[s.groupStart[g]].receiver)] = g;
  }

  void run() { visit(s_.h.root()); }

 private:
  std::size_t key(NodeId n) const { return n.isCluster() ? E_ + n.index() : std::size_t(n.index()); }

  void visit(NodeId n) {
    if (!s_.isOwned(n)) return;
    if (std::uint32_t g = group_[key(n)]; g != kNone) {
      std::vector<IncidentSample> samples;
      samples.reserve(s_.groupStart[g + 1] - s_.groupStart[g]);
      for (std::uint32_t i = s_.groupStart[g]; i < s_.groupStart[g + 1]; ++i) samples.push_back(s_.sampleOf(s_.links[i]));
      s_.samples.fetch_add(samples.size(), std::memory_order_relaxed);
      s_.ext->gather(n, samples);
    }
    // Subtrees run in parallel: an owned node's gather may reflect (Radiance Clustering), which costs
    // far more than a task.
    auto kids = s_.h.children(n);
    if (kids.size() > 1) {
      tbb::parallel_for(std::size_t(0), kids.size(), [&](std::size_t k) {
        s_.clkGather.sawThread();
        visit(kids[k]);
      });
    } else {
      for (NodeId k : kids) visit(k);
    }
  }

  SolverState& s_;
  const std::size_t E_;
  std::vector<std::uint32_t> group_;  // node key (elements, then clusters) -> its receiver group, or kNone
};

}  // namespace

void callGatherHooks(SolverState& s) {
  if (!s.ext || s.groupStart.size() < 2) return;
  GatherHooks(s).run();
}

}  // namespace hr::detail
