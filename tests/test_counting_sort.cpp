// The parallel counting sort that groups links by receiver (base_radiosity/bright/src/counting_sort.h): it
// must give std::stable_sort's order, items left out excluded, whatever the number of blocks, which
// follows the thread count. Solver-level determinism over many links is in test_robustness.cpp.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "counting_sort.h"

namespace {

TEST(CountingSort, StableOrderForAnyThreadCountAndSize) {
  std::mt19937 rng(3);
  // Sizes below, at and well above one block (8192 items), so that 1, 2 and 4 threads cut them
  // into different numbers of blocks.
  for (std::size_t n : {0u, 1u, 8191u, 8192u, 30000u, 200000u}) {
    const std::size_t keys = 997;
    std::vector<std::size_t> key(n);
    // Key `keys` leaves an item out; about one in ten is.
    for (auto& k : key) k = rng() % 10 == 0 ? keys : rng() % keys;
    std::vector<std::uint32_t> want(n);
    std::iota(want.begin(), want.end(), 0u);
    std::stable_sort(want.begin(), want.end(), [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
    want.resize(std::size_t(std::count_if(key.begin(), key.end(), [&](std::size_t k) { return k != keys; })));
    std::vector<std::uint32_t> wantStart;
    for (std::size_t i = 0; i < want.size(); ++i)
      if (i == 0 || key[want[i]] != key[want[i - 1]]) wantStart.push_back(std::uint32_t(i));
    wantStart.push_back(std::uint32_t(want.size()));
    for (int threads : {1, 2, 4}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
      std::vector<std::uint32_t> got(n, ~0u);
      auto start = hr::detail::countingSort(
          n, keys, [&](std::size_t i) { return key[i]; }, [&](std::size_t i, std::uint32_t p) { got[p] = std::uint32_t(i); });
      got.resize(want.size());
      EXPECT_EQ(got, want) << n << " items, " << threads << " threads";
      EXPECT_EQ(start, wantStart) << n << " items, " << threads << " threads";
    }
  }
}

}  // namespace
