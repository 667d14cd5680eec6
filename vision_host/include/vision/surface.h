// One scene primitive kept whole as an initial patch of the VISION-like host: a map from the unit
// parameter square to the surface (point, unit normal, area element), because this host's elements
// are rectangles of that square. Quads and triangles use the bilinear map (a triangle is a quad with
// two corners at its apex), convex (star-shaped) polygons a map about their area centroid, disks and
// rings a polar map, spheres, cylinders and cones their angle-height maps. All but the bilinear map
// are equal-area in the primitive's own frame: a rectangle's area is its share of the whole, so
// splitting a rectangle splits the area in proportion (and under a similarity transform stays so).
#pragma once
#include <hr/scene.h>

#include <vector>

namespace vision {

using hr::Vec3;

enum class SurfaceKind : std::uint8_t {
  Bilinear,  // a planar quad or triangle, corners in world space
  Star,      // a planar polygon star-shaped about its area centroid, world space
  Annulus,   // disk or ring in the local z = 0 plane
  Sphere,    // local centre 0, radius r0
  Frustum,   // cylinder or cone frustum along local z from 0 to h, radius r0 at 0 and r1 at h
};

struct Rect {
  double u0 = 0.0, u1 = 1.0, v0 = 0.0, v1 = 1.0;
  double du() const { return u1 - u0; }
  double dv() const { return v1 - v0; }
};

class Surface {
 public:
  SurfaceKind kind = SurfaceKind::Bilinear;
  std::uint32_t material = 0, object = 0;
  bool inward = false;  // normals face the inside (a closed sphere, cylinder or cone seen from within)

  /// World point at (u, v) in [0, 1]^2.
  Vec3 point(double u, double v) const;
  /// Unit normal (the side that emits and reflects) at (u, v).
  Vec3 normal(double u, double v) const;
  /// Area element |dP/du x dP/dv| at (u, v), m^2 per unit parameter area.
  double jacobian(double u, double v) const;
  /// Flat: every normal is the same and every element's image is a planar region.
  bool planar() const { return kind == SurfaceKind::Bilinear || kind == SurfaceKind::Star || kind == SurfaceKind::Annulus; }
  /// Points of the surface see each other (an inward sphere, cylinder or cone): an element may send
  /// to itself and to its relatives. A planar or convex surface never lights itself.
  bool concave() const { return inward && !planar(); }
  /// Edges of a rectangle's image are straight lines (its outline polygon is exact).
  bool straightEdges() const { return kind == SurfaceKind::Bilinear || kind == SurfaceKind::Star; }
  /// Parameter values at which the outline of a rectangle must keep a corner (the star map's polygon
  /// vertices, in u); empty for the other kinds.
  const std::vector<double>& breaks() const { return breaks_; }

  // Construction (surface_build.cpp).
  static Surface bilinear(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
  /// Returns false when the polygon is not star-shaped about its area centroid.
  static bool star(const std::vector<Vec3>& pts, Surface& out);
  static Surface annulus(const glm::dmat4& toWorld, double rInner, double rOuter);
  static Surface sphere(const glm::dmat4& toWorld, double radius);
  static Surface frustum(const glm::dmat4& toWorld, double r0, double r1, double height);

  // Local geometry of the quadric kinds (for the visibility module): canonical parameters, the
  // local-to-world affine map and its inverse. A Star surface keeps its area in r0.
  double r0 = 0.0, r1 = 0.0, height = 0.0;
  glm::dmat4 toWorld{1.0}, toLocal{1.0};
  glm::dmat3 normalMatrix{1.0};  // inverse transpose of toWorld's linear part
  std::vector<Vec3> pts;         // Bilinear: 4 corners; Star: centroid then the boundary
  Vec3 flatNormal{0.0, 0.0, 1.0};  // Bilinear, Star

  /// Local point and outward local normal of the quadric kinds at (u, v).
  Vec3 localPoint(double u, double v) const;
  Vec3 localNormal(double u, double v) const;

 private:
  void setFrame(const glm::dmat4& m);
  Vec3 starBoundary(double u) const;
  std::vector<double> breaks_;  // Star: cumulative area fractions at the boundary's vertices
};

struct SurfaceReport {
  std::size_t objects = 0;              // scene objects read
  std::size_t split = 0;                // extra surfaces from polygons that are not star-shaped
  std::size_t nonPlanarQuads = 0;       // quads split into two triangles
  std::size_t dropped = 0;              // zero-area faces
};

/// Every scene object as whole surfaces: one per primitive, box face and mesh face; polygons that are
/// not star-shaped about their centroid are triangulated (counted). Materials of mesh files are
/// appended to scene.materials, as the tessellating host does. Throws hr::InputError for scenes
/// without an emitter.
std::vector<Surface> buildSurfaces(hr::Scene& scene, SurfaceReport& report);

}  // namespace vision
