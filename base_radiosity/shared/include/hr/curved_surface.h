// A scene's curved primitives as the display needs them: the exact normal at a point. A glossy
// highlight on a sphere sits where the sphere's own normal mirrors the light, so a tessellating host
// shades its flat facets at the normal of the surface they approximate (Phong's idea, with the true
// normal instead of an average of facets), and a host that keeps surfaces whole shades its display
// cells the same way. The solution carries them as the "surfaces" section, one entry per object, so
// a saved solution shades as a fresh one without the scene; a few hundred bytes per curved object,
// where per-element normals cost 96 bytes for each of a glossy scene's hundreds of thousands.
#pragma once
#include <hr/scene.h>

#include <cstdint>
#include <string>
#include <vector>

namespace hr {

enum class CurvedKind : std::uint8_t { None = 0, Sphere = 1, Frustum = 2 };

/// A quadric in its own frame, carried to the world by an affine map (an ellipsoid under non-uniform
/// scale is still exact): a sphere of radius r0 about the origin, or a frustum along +z from radius
/// r0 at z = 0 to r1 at z = height (a cylinder when they agree, a cone when one is 0).
struct CurvedSurface {
  CurvedKind kind = CurvedKind::None;
  glm::dmat4 toWorld{1.0}, toLocal{1.0};  // set together by setFrame()
  glm::dmat3 normalToWorld{1.0};          // the inverse transpose: normals stay normal under scale
  double r0 = 0.0, r1 = 0.0, height = 0.0;
  bool inward = false;

  void setFrame(const glm::dmat4& m);

  /// The unit normal (outward, or inward for an inward primitive) at the surface point the quadric's
  /// own radial direction through p meets; Vec3(0) where that is undefined (a frustum's axis, a
  /// sphere's centre) or for kind None.
  Vec3 normalAt(const Vec3& p) const;
  /// Where a viewer looking back along unit dir (toward the viewer) through p first meets the surface:
  /// a ray that hit a display facet near the surface, moved onto the surface itself (a highlight sits
  /// where the surface's own point mirrors its source). p where the line misses the quadric or kind is
  /// None.
  Vec3 meet(const Vec3& p, const Vec3& dir) const;
};

/// The frame whose z axis is the unit axis and whose origin is origin (x and y any orthonormal pair).
glm::dmat4 frameAt(const Vec3& origin, const Vec3& axis);

/// One entry per scene object, in file order: spheres, cylinders and cones curved, the rest None.
std::vector<CurvedSurface> curvedSurfaces(const Scene& scene);
/// Whether any entry is curved (a scene of planes needs no "surfaces" section).
bool anyCurved(const std::vector<CurvedSurface>& surfaces);

/// The ".ghrs" section: kSurfaces, the entry count, then per entry its kind and, if curved, its
/// frame (16 doubles), r0, r1, height and inward.
inline constexpr const char* kSurfaces = "surfaces";
std::string encodeSurfaces(const std::vector<CurvedSurface>& surfaces);
/// Throws InputError naming the section when it does not hold objectCount entries exactly, a kind is
/// unknown, or a value is not finite, a frame not invertible, or a radius or height out of range.
std::vector<CurvedSurface> decodeSurfaces(const std::string& payload, std::uint32_t objectCount);

}  // namespace hr
