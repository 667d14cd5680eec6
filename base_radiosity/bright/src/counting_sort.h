// A stable counting sort in parallel, for grouping links by receiver (group_links.cpp, and the
// receiver pass in refine.cpp). Serially each such grouping reads every link twice from memory;
// in blocks, each counted and placed by one task, it runs on every core. A stable sort has a single
// result, so the number of blocks (taken from the thread count) changes the speed, never the order.
#pragma once
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace hr::detail {

/// Sorts items 0..n-1 by key(i) in [0, keys), stably; key(i) == keys leaves item i out. place(i, p)
/// is called once for every item sorted, with its position p (from different threads, each p once).
/// Returns the first position of every key that has items, in key order, then the number sorted.
template <class Key, class Place>
std::vector<std::uint32_t> countingSort(std::size_t n, std::size_t keys, Key key, Place place) {
  // Each block has a histogram over every key (the last bucket: items left out), hence a cap. The
  // threads: the arena's, or fewer if a global_control limits them (the arena does not know).
  const std::size_t threads = std::max<std::size_t>(
      1, std::min<std::size_t>(std::size_t(tbb::this_task_arena::max_concurrency()),
                               tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
  // Up to four blocks per thread (balance), but the histograms hold at most four counters per item
  // (a tenth of a link's bytes; 64 blocks over a 300 k-element scene's keys would take 77 MB), and
  // one thread sorts in one block, as the serial version did.
  const std::size_t K = keys + 1;
  const std::size_t blocks = threads == 1 ? 1
                                          : std::clamp<std::size_t>(std::min(n / 8192, 4 * n / K), 1,
                                                                    std::min<std::size_t>(4 * threads, 64));
  auto first = [&](std::size_t b) { return n * b / blocks; };
  std::vector<std::uint32_t> pos(blocks * K, 0);  // per block and key: count, then the next position
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
    std::uint32_t* count = pos.data() + b * K;
    for (std::size_t i = first(b); i != first(b + 1); ++i) ++count[key(i)];
  });
  // Key by key, block by block: a key's items keep their order across blocks.
  std::vector<std::uint32_t> start;
  std::uint32_t next = 0;
  for (std::size_t k = 0; k < keys; ++k) {
    const std::uint32_t at = next;
    for (std::size_t b = 0; b < blocks; ++b) {
      const std::uint32_t c = pos[b * K + k];
      pos[b * K + k] = next;
      next += c;
    }
    if (next > at) start.push_back(at);
  }
  start.push_back(next);
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
    std::uint32_t* at = pos.data() + b * K;
    for (std::size_t i = first(b); i != first(b + 1); ++i) {
      const std::size_t k = key(i);
      if (k != keys) place(i, at[k]++);
    }
  });
  return start;
}

}  // namespace hr::detail
