// One path in flight: the ray it follows next, the throughput and radiance gathered so far, and the
// light sample its last vertex waits to have confirmed by a shadow ray. Plain data, reused from
// sample to sample so that tracing allocates nothing.
#pragma once
#include <hr/geometry.h>
#include <ref/sample_stream.h>

namespace ref {

struct PathState {
  hr::Vec3 org{0.0}, dir{0.0, 0.0, 1.0};  // the next ray
  hr::Rgb throughput{1.0}, radiance{0.0};
  double prevPdf = 0.0;  // density of the BRDF sample that made the ray; 0 for a camera ray
  int depth = 0;         // scattering vertices so far
  bool alive = false;    // the ray still has to be traced
  // The pending light sample: added when nothing lies between from and to.
  bool shadow = false;
  hr::Vec3 shadowFrom{0.0}, shadowTo{0.0};
  hr::Rgb shadowRadiance{0.0};
  SampleStream sampler;

  void start(const hr::Vec3& o, const hr::Vec3& d, const SampleStream& s) {
    org = o, dir = d;
    throughput = hr::Rgb(1.0), radiance = hr::Rgb(0.0);
    prevPdf = 0.0, depth = 0, alive = true, shadow = false;
    sampler = s;
  }
};

}  // namespace ref
