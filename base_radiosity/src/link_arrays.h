// Link arrays filled in parallel. Refinement moves every link several times per pass (kept, split,
// grouped by receiver): copied serially into freshly allocated arrays this was a third of refinement
// on the Soda Shoppe, most of it the kernel's first touch of new pages (glibc maps arrays this large
// afresh on every allocation). Here arrays grow with their pages touched by all threads, the copies
// are parallel, and every position is fixed before any thread writes, so the contents never depend
// on the thread count.
#pragma once
#include <cstdint>
#include <vector>

#include "solver_state.h"

namespace hr::detail {

/// Makes room for n links in v, keeping its links: a new array's pages are touched in parallel before
/// the links are copied into it (in parallel).
void reserveLinks(std::vector<Link>& v, std::size_t n);

/// Resizes v to n links, keeping the first min(size, n). When the capacity must grow it grows by half
/// at least (reserveLinks), so that appending round after round reallocates rarely. New links are
/// value-initialised.
void growLinks(std::vector<Link>& v, std::size_t n);

/// dst[i] = src[i] for i < n, in parallel.
void copyLinks(const Link* src, std::size_t n, Link* dst);

/// Sorts links by receiver, stably (a parallel counting sort on a dense key: elements first, then
/// clusters), and sets start to the receivers' ranges (one entry per receiver, then v.size()). spare
/// is scratch: it returns holding v's old array, for reuse.
void groupByReceiver(const Hierarchy& h, std::vector<Link>& v, std::vector<std::uint32_t>& start,
                     std::vector<Link>& spare);

}  // namespace hr::detail
