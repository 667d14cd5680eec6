// Small counter-based random numbers: a stream is a hash of (seed, keys), so every link and every
// leaf draws the same numbers whatever the thread count or the order of evaluation.
#pragma once
#include <cstdint>

namespace hr {

inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

class Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t a, std::uint64_t b = 0) : s_(mix64(mix64(seed ^ mix64(a)) ^ b)) {}
  std::uint64_t next() { return s_ = mix64(s_); }
  /// Uniform in [0, 1).
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t s_;
};

}  // namespace hr
