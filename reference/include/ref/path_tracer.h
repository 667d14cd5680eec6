// The reference: a path tracer over the same tessellated scene, materials and cameras as the
// radiosity solver, with next-event estimation of the area emitters combined with BRDF sampling by
// multiple importance sampling (power heuristic), and Russian roulette. Surfaces are one-sided as in
// the solver: emitters emit from the front, backs are black. Paths advance 16 at a time through
// Embree's packet queries; every pixel sample draws from its own counter-based stream and the image
// is cut into fixed tiles, so a run depends on the seed and the sample count, not on the threads.
#pragma once
#include <glossy/brdf.h>
#include <hr/geometry.h>
#include <hr/output.h>
#include <hr/progress.h>
#include <hr/rng.h>
#include <hr/visibility.h>
#include <ref/alias_table.h>
#include <ref/path_state.h>

#include <memory>
#include <vector>

namespace ref {

using hr::Rgb;
using hr::Vec3;

struct Options {
  int spp = 64;            // samples per pixel (rounded up to whole rounds of kReplicates), unless timeS > 0
  double timeS = 0.0;      // > 0: keep adding passes of passSpp until the time is spent
  int passSpp = 8;
  int maxDepth = 64;       // bounces (scattering vertices); Russian roulette ends most paths long before
  std::uint64_t seed = 1;
};

struct CameraResult {
  hr::Image image;                 // mean radiance, W/(m^2 sr)
  std::vector<float> variance;     // per pixel and channel: variance of the mean, (W/(m^2 sr))^2
  int spp = 0;
  double seconds = 0.0;            // wall time of the sampling passes
  double cpuSeconds = 0.0;         // process CPU time over the same span (all threads)
  std::uint64_t paths = 0;
  double meanLuminance = 0.0;      // image mean, W/(m^2 sr)
  double relStdError = 0.0;        // estimated standard error of that mean, relative
  std::uint64_t nonFinite = 0;     // samples dropped as non-finite (should stay 0)
};

class PathTracer {
 public:
  PathTracer(const hr::Scene& scene, std::vector<hr::Patch> patches);
  ~PathTracer();

  /// Radiance arriving at org from direction -dir (i.e. seen looking along dir), W/(m^2 sr); one
  /// path, traced ray by ray (the same estimator render() runs 16 paths at a time).
  Rgb radiance(const Vec3& org, const Vec3& dir, hr::Rng& rng, int maxDepth) const;
  CameraResult render(const hr::Camera& cam, const Options& o, hr::Progress* progress = nullptr) const;

  const std::vector<hr::Patch>& patches() const { return patches_; }
  const hr::Visibility& visibility() const { return *vis_; }

  /// Consumes the hit of the path's current ray: emission (MIS-weighted against the previous
  /// vertex's light sample), then, unless the path ends here, a light sample waiting for its shadow
  /// ray and the next ray drawn from the BRDF.
  void shade(PathState& p, const hr::SurfaceHit& hit, int maxDepth) const;

 private:
  /// Per material: what the estimator needs, decided once.
  struct Surface {
    glossy::ModifiedPhong brdf;
    Rgb emission{0.0};
    bool emits = false;
    bool reflects = false;
    bool lambert = false;  // no specular part: f = rho_d / pi, sampled by cosine exactly
  };
  /// An emitting patch ready for sampling: corner v0 and edges to the other corners (a quad is the
  /// triangles v0 v1 v2 and v0 v2 v3, the first chosen with probability `split`).
  struct Emitter {
    Vec3 v0, e1, e2, e3;
    double split = 1.0;
    std::uint32_t patch = 0;
  };
  /// Per patch, what a vertex needs beyond the patch itself: a tangent frame for direction
  /// sampling and the area density of light samples (0 for patches that do not emit).
  struct Frame {
    Vec3 t, b;
    double lightDensity = 0.0;  // probability of picking the patch as light / its area, 1/m^2
  };

  std::vector<hr::Patch> patches_;
  std::unique_ptr<hr::Visibility> vis_;
  std::vector<Surface> surfaces_;   // per material
  std::vector<Frame> frames_;       // per patch
  std::vector<Emitter> emitters_;   // emitting patches, in patch order
  AliasTable lights_;               // over emitters_, by emitted power
  double eps_ = 0.0;
};

}  // namespace ref
