// Links grouped by receiver (link_arrays.h): gathering and push/pull walk the links receiver by
// receiver. The grouping runs once per refinement pass over every link; serially it was a sixth of
// refinement on the Soda Shoppe.
#include "counting_sort.h"
#include "link_arrays.h"

namespace hr::detail {

void groupByReceiver(const Hierarchy& h, std::vector<Link>& v, std::vector<std::uint32_t>& start,
                     std::vector<Link>& spare) {
  // A dense key: elements first, then clusters.
  const std::size_t E = h.elements().size();
  auto key = [&](std::size_t i) {
    const NodeId r = v[i].receiver;
    return r.isCluster() ? E + r.index() : std::size_t(r.index());
  };
  spare.clear();
  growLinks(spare, v.size());
  start = countingSort(v.size(), E + h.clusters().size(), key, [&](std::size_t i, std::uint32_t p) { spare[p] = v[i]; });
  v.swap(spare);
}

}  // namespace hr::detail
