// The reference: a path tracer over the same tessellated scene, materials and cameras as the
// radiosity solver, with next-event estimation of the area emitters combined with BRDF sampling by
// multiple importance sampling (power heuristic), and Russian roulette. Surfaces are one-sided as in
// the solver: emitters emit from the front, backs are black. Every pixel sample draws from its own
// counter-based stream, so a run depends on the seed and the sample count, not on the threads.
#pragma once
#include <glossy/brdf.h>
#include <hr/geometry.h>
#include <hr/output.h>
#include <hr/progress.h>
#include <hr/rng.h>
#include <hr/visibility.h>

#include <memory>
#include <vector>

namespace ref {

using hr::Rgb;
using hr::Vec3;

struct Options {
  int spp = 64;            // samples per pixel, unless timeS > 0
  double timeS = 0.0;      // > 0: keep adding passes of passSpp until the time is spent
  int passSpp = 8;
  int maxDepth = 64;       // bounces; Russian roulette ends most paths long before
  std::uint64_t seed = 1;
};

struct CameraResult {
  hr::Image image;                 // mean radiance, W/(m^2 sr)
  std::vector<float> variance;     // per pixel and channel: variance of the mean, (W/(m^2 sr))^2
  int spp = 0;
  double seconds = 0.0;
  std::uint64_t paths = 0;
  double meanLuminance = 0.0;      // image mean, W/(m^2 sr)
  double relStdError = 0.0;        // estimated standard error of that mean, relative
  bool varianceKnown = true;       // false with one sample per pixel: variance and relStdError are 0, unknown
  std::uint64_t nonFinite = 0;     // samples dropped as non-finite (should stay 0)
};

class PathTracer {
 public:
  PathTracer(const hr::Scene& scene, std::vector<hr::Patch> patches);
  ~PathTracer();

  /// Radiance arriving at org from direction -dir (i.e. seen looking along dir), W/(m^2 sr).
  Rgb radiance(const Vec3& org, const Vec3& dir, hr::Rng& rng, int maxDepth) const;
  CameraResult render(const hr::Camera& cam, const Options& o, hr::Progress* progress = nullptr) const;

  const std::vector<hr::Patch>& patches() const { return patches_; }

 private:
  struct Light {
    std::uint32_t patch;
    double cdf;  // cumulative share of emitted power
  };
  double lightPdf(std::uint32_t patch, const Vec3& from, const Vec3& at) const;

  std::vector<hr::Patch> patches_;
  std::unique_ptr<hr::Visibility> vis_;
  std::vector<glossy::ModifiedPhong> brdf_;  // per material
  std::vector<Rgb> emission_;                // per material, radiance W/(m^2 sr)
  std::vector<Light> lights_;
  std::vector<double> choose_;               // per patch: probability of being picked as light
};

}  // namespace ref
