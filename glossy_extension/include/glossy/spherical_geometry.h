// Spherical geometry the extension's queries need beyond the bases themselves: caps (the oracle's
// cone and a conservative hull of a cell), convex spherical polygons clipped by great circles (exact
// overlap of two cells in different frames), uniform sampling of a spherical triangle (Arvo 1995) and
// the projected solid angle of a triangle (a cell's mean cosine, for display at grazing angles).
#pragma once
#include <glossy/sphere.h>

namespace glossy {

/// The directions within an angle of a unit centre, kept as the cosine and sine of that angle.
struct Cap {
  Vec3 centre{0, 0, 1};
  double cosR = -1.0, sinR = 0.0;  // the whole sphere by default

  static Cap cone(const Vec3& axis, double cosHalfAngle);
  /// A cap holding the whole spherical triangle (its corners' farthest from the centre direction).
  static Cap around(const FaceTri& t);
  bool whole() const { return cosR <= -1.0; }
  /// Whether the caps may share a direction; errs on the side of yes by about 1e-9 in cosine.
  bool overlaps(const Cap& o) const;
};

/// Whether a cone and a spherical triangle share a direction: the axis lies in the triangle or an
/// edge arc comes within the cone's angle of it. Exact up to about 1e-9 in cosine, erring on yes.
bool meets(const Cap& cone, const FaceTri& t);

/// A convex spherical polygon with unit-vector corners (a clipped triangle has at most 6).
struct SphericalPolygon {
  Vec3 v[8];
  int n = 0;
  static SphericalPolygon triangle(const Vec3& a, const Vec3& b, const Vec3& c) { return {{a, b, c}, 3}; }
  /// Keeps the part with dot(x, planeNormal) >= 0 (a hemisphere bounded by a great circle).
  void clip(const Vec3& planeNormal);
  /// Solid angle, sr (fan of exact triangle solid angles).
  double area() const;
};

/// The three inward normals of a spherical triangle's edge planes: x is inside iff all dots >= 0.
void insideNormals(const Vec3& a, const Vec3& b, const Vec3& c, Vec3 out[3]);

/// A direction uniformly distributed over the spherical triangle (a, b, c) from u1, u2 in [0, 1)
/// (Arvo, "Stratified sampling of spherical triangles", SIGGRAPH 1995).
Vec3 sampleTriangle(const Vec3& a, const Vec3& b, const Vec3& c, double u1, double u2);

/// The integral of dot(n, w) over the triangle (sr), for a triangle on the positive side of n's
/// plane: the edge formula (Lambert), exact.
double projectedSolidAngle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n);

}  // namespace glossy
