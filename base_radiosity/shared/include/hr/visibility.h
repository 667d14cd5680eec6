// Embree 3 behind one small class: shadow segments (bundled 16 at a time, as the rays of one link
// are) and primary-ray intersection for rendering. Everything else in the project sees only this.
#pragma once
#include <hr/coplanar.h>
#include <hr/geometry.h>

#include <memory>
#include <vector>

namespace hr {

struct SurfaceHit {
  bool hit = false;
  double t = 0.0;
  std::uint32_t patch = kNone;
};

class Visibility {
 public:
  explicit Visibility(const std::vector<Patch>& patches);
  ~Visibility();
  Visibility(const Visibility&) = delete;
  Visibility& operator=(const Visibility&) = delete;

  /// For each segment from[i] -> to[i], sets blocked[i] when any surface lies strictly between the
  /// ends. Both ends are trimmed by epsilon() so that the surfaces the ends lie on do not count.
  void occluded(const Vec3* from, const Vec3* to, int count, bool* blocked) const;
  bool occluded(const Vec3& from, const Vec3& to) const;
  /// True when the ray from org along unit dir hits nothing (used for escaped energy).
  bool escapes(const Vec3& org, const Vec3& dir) const;
  SurfaceHit intersect(const Vec3& org, const Vec3& dir) const;
  /// Closest hit of a ray leaving patch `from` at org (a point on it, not lifted): hits on `from`
  /// itself and, within epsilon() of org, on patches in its plane facing its way are ignored. Two
  /// surfaces closer than the lift of a lifted origin (facing lamps 1e-6 m apart) stay apart.
  SurfaceHit intersectFrom(const Vec3& org, const Vec3& dir, std::uint32_t from) const;
  /// The patch that covers point x of patch p where coplanar or near-coplanar patches overlap
  /// (coplanar.h), or kNone.
  std::uint32_t coverOf(std::uint32_t p, const Vec3& x) const;
  /// Whether any patch covers part of patch p (coverOf can answer other than kNone).
  bool partlyCovered(std::uint32_t p) const;
  /// The closest hit of each ray org[i] + t dir[i], t > 0, as intersect() answers one; traced 16 at a
  /// time (rtcIntersect16) so that a batch of rays, coherent or not, shares the call and node tests.
  void intersect(const Vec3* org, const Vec3* dir, int count, SurfaceHit* hits) const;
  /// Robust traversal (the default) is watertight: no ray slips between two triangles that share an
  /// edge. Without it Embree's traversal takes about 30 % fewer instructions, and a ray passing within
  /// float rounding of an edge may miss both triangles. Rebuilds the BVH on one thread, as the
  /// constructor does, so answers stay independent of the thread count.
  void setRobust(bool robust);
  /// Absolute trimming distance: a small fraction of the scene's size, so scaled scenes behave alike.
  double epsilon() const { return eps_; }
  /// The raw Embree scene, for benchmarks that compare against plain rtcOccluded1 loops.
  void* rawScene() const;

 private:
  SurfaceHit trace(const Vec3& org, const Vec3& dir, void* context) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double eps_ = 1e-6;
};

}  // namespace hr
