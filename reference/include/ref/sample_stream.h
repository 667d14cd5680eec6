// The uniform numbers one pixel sample consumes, asked for by dimension in a fixed order (camera,
// then per vertex: light choice, light point, BRDF lobe, BRDF direction, roulette). A stream is a
// function of (seed, pixel, sample index) only, so the order samples are traced in changes nothing.
//
// Image samples are randomised quasi-Monte Carlo: every 1D or 2D request is a point of the Sobol
// (0,2)-sequence, Owen-scrambled and with its order shuffled by hashing (Burley 2020, "Practical
// Hash-based Owen Scrambling"), with a fresh scramble per pixel, replicate and dimension ("padding").
// The first 2^m points of a stream fill every elementary interval of area 2^-m once, which is what
// removes most of the noise at edges and in soft shadows. Sample k of a pixel belongs to replicate
// k mod kReplicates, and each replicate is scrambled independently: the replicates' means are
// independent, identically distributed estimates, so their spread is an honest variance of the
// pixel mean (the spread of the samples themselves would overstate it, since they are not
// independent).
#pragma once
#include <hr/rng.h>

#include <cstdint>

namespace ref {

struct Uv {
  double u = 0.0, v = 0.0;
};

/// Independently scrambled sequences per pixel; sample counts are multiples of this.
constexpr int kReplicates = 8;
/// Requests (1D or 2D) served by Sobol points: the camera's and the first three vertices'. Deeper
/// dimensions carry little of the image and gain nothing measurable from stratification, so they get
/// plain hashed numbers, at a fifth of the cost.
constexpr std::uint32_t kSobolRequests = 16;

namespace sobol {

inline std::uint32_t reverseBits(std::uint32_t x) {
  x = __builtin_bswap32(x);  // bytes in one instruction, then the bits within each byte
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  return ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
}

/// Laine-Karras style hash on bit-reversed values (constants from Vegdahl's improvement of Burley's):
/// every bit is flipped depending only on the bits below it, which is Owen's nested scrambling.
inline std::uint32_t laineKarras(std::uint32_t x, std::uint32_t seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

/// Owen's nested uniform scramble of a 32-bit fixed-point value in [0, 1).
inline std::uint32_t owen(std::uint32_t x, std::uint32_t seed) { return reverseBits(laineKarras(reverseBits(x), seed)); }

/// Second dimension of the Sobol sequence (the first is the bit-reversed index): direction numbers
/// v_0 = 2^31, v_k = v_{k-1} xor v_{k-1} >> 1 (primitive polynomial x + 1). The xor over the index's
/// set bits is looked up a byte at a time: a bit loop cost a fifth of the tracer's time.
struct Dimension1Table {
  std::uint32_t byte[4][256];
  constexpr Dimension1Table() : byte{} {
    std::uint32_t v[32] = {};
    v[0] = 0x80000000u;
    for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
    for (int b = 0; b < 4; ++b)
      for (int x = 0; x < 256; ++x) {
        std::uint32_t r = 0;
        for (int k = 0; k < 8; ++k)
          if (x & (1 << k)) r ^= v[8 * b + k];
        byte[b][x] = r;
      }
  }
};
inline constexpr Dimension1Table kDimension1{};

inline std::uint32_t dimension1(std::uint32_t index) {
  return kDimension1.byte[0][index & 0xFFu] ^ kDimension1.byte[1][(index >> 8) & 0xFFu] ^
         kDimension1.byte[2][(index >> 16) & 0xFFu] ^ kDimension1.byte[3][index >> 24];
}

inline double toUnit(std::uint32_t x) { return double(x) * 0x1.0p-32; }

}  // namespace sobol

class SampleStream {
 public:
  SampleStream() : rng_(0, 0) {}
  /// Sample `index` of `pixel`: replicate index mod kReplicates, point index / kReplicates of it.
  SampleStream(std::uint64_t seed, std::uint64_t pixel, std::uint64_t index)
      : rng_(0, 0),
        key_(hr::mix64(hr::mix64(seed ^ hr::mix64(pixel)) ^ (index % kReplicates))),
        reversedPoint_(sobol::reverseBits(static_cast<std::uint32_t>(index / kReplicates))),
        qmc_(true) {}
  /// Plain independent numbers continuing a random stream (single paths traced outside an image).
  explicit SampleStream(hr::Rng rng) : rng_(rng) {}

  // owen(x, s) = reverse(LK(reverse(x), s)): the Sobol values below are written with as few bit
  // reversals as that identity allows (the first dimension is itself the reversed index).
  double get1D() {
    if (!qmc_) return rng_.uniform();
    std::uint64_t h = dimensionHash();
    if (dim_ > kSobolRequests) return double(plain(h) >> 11) * 0x1.0p-53;
    std::uint32_t i = shuffled(h);
    return sobol::toUnit(sobol::reverseBits(sobol::laineKarras(i, std::uint32_t(h >> 32))));
  }
  Uv get2D() {
    if (!qmc_) {
      double u = rng_.uniform();
      return {u, rng_.uniform()};
    }
    std::uint64_t h = dimensionHash();
    if (dim_ > kSobolRequests) {
      std::uint64_t r = plain(h);
      return {sobol::toUnit(std::uint32_t(r >> 32)), sobol::toUnit(std::uint32_t(r))};
    }
    std::uint32_t i = shuffled(h);
    std::uint32_t h2 = std::uint32_t(((h ^ (h >> 29)) * 0xbf58476d1ce4e5b9ull) >> 32);
    return {sobol::toUnit(sobol::reverseBits(sobol::laineKarras(i, std::uint32_t(h >> 32)))),
            sobol::toUnit(sobol::owen(sobol::dimension1(i), h2))};
  }

  /// Passes over a dimension the caller does not need (one emitter, a Lambertian lobe choice), so that
  /// the dimensions after it keep their place.
  void skip() {
    if (qmc_) ++dim_;
  }

 private:
  std::uint64_t dimensionHash() { return hr::mix64(key_ ^ (0x9e3779b97f4a7c15ull * ++dim_)); }
  /// A plain random number for this dimension and this point (the dimension's hash alone would
  /// repeat across the points of a replicate).
  std::uint64_t plain(std::uint64_t h) const { return hr::mix64(h ^ reversedPoint_); }
  /// The point's index, Owen-scrambled: the first 2^m indices map onto an aligned block of 2^m
  /// indices, so every prefix of a power-of-two length is still a whole net, yet dimensions are
  /// decorrelated.
  std::uint32_t shuffled(std::uint64_t h) const {
    return sobol::reverseBits(sobol::laineKarras(reversedPoint_, std::uint32_t(h)));
  }

  hr::Rng rng_;
  std::uint64_t key_ = 0;
  std::uint32_t reversedPoint_ = 0;
  std::uint32_t dim_ = 0;
  bool qmc_ = false;
};

}  // namespace ref
