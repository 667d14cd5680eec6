// The uniform numbers one pixel sample consumes, asked for by dimension in a fixed order (camera,
// then per vertex: light choice, light point, BRDF lobe, BRDF direction, roulette). A stream is a
// function of (seed, pixel, sample index) only, so the order samples are traced in changes nothing.
#pragma once
#include <hr/rng.h>

namespace ref {

struct Uv {
  double u = 0.0, v = 0.0;
};

class SampleStream {
 public:
  SampleStream() : rng_(0, 0) {}
  SampleStream(std::uint64_t seed, std::uint64_t pixel, std::uint64_t index) : rng_(seed, pixel, index) {}
  /// Continues an existing random stream (for single paths traced outside an image).
  explicit SampleStream(hr::Rng rng) : rng_(rng) {}

  double get1D() { return rng_.uniform(); }
  Uv get2D() {
    double u = rng_.uniform();
    return {u, rng_.uniform()};
  }

 private:
  hr::Rng rng_;
};

}  // namespace ref
