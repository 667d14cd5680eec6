// Visibility against the exact surfaces, not a tessellation: Embree triangles for the flat kinds with
// straight edges (exact), Embree user geometry for disks, rings, spheres, cylinders and cones
// (each ray taken into the primitive's own frame and intersected with the quadric in double
// precision), so the shadow of a sphere is round and a cylinder has no facets.
#pragma once
#include <vision/surface.h>

#include <memory>
#include <vector>

namespace vision {

struct CurvedHit {
  bool hit = false;
  double t = 0.0;
  std::uint32_t surface = hr::kNone;
  bool front = false;  // the ray met the surface's emitting side
};

class CurvedVisibility {
 public:
  explicit CurvedVisibility(const std::vector<Surface>& surfaces);
  ~CurvedVisibility();
  CurvedVisibility(const CurvedVisibility&) = delete;
  CurvedVisibility& operator=(const CurvedVisibility&) = delete;

  /// blocked[i]: a surface lies strictly between from[i] and to[i], both ends trimmed by epsilon().
  /// Traced 16 at a time.
  void occluded(const Vec3* from, const Vec3* to, int count, bool* blocked) const;
  /// Closest hit of org + t dir, t > epsilon() / |dir|.
  CurvedHit intersect(const Vec3& org, const Vec3& dir) const;
  /// Absolute trimming distance: 1e-5 of the scene's diagonal.
  double epsilon() const { return eps_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double eps_ = 1e-6;
};

}  // namespace vision
