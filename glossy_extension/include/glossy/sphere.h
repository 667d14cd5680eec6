// Spherical geometry shared by the directional bases: exact solid angles of spherical triangles, and
// the 1->4 triangle descent that both the octahedron (Haar) and the tetrahedron (non-adaptive) use.
// Cells are planar triangles on a polyhedron's face seen from the centre: central projection maps
// straight edges to great circles, so every cell is an exact spherical triangle.
#pragma once
#include <hr/extension.h>

#include <cmath>

namespace glossy {

using hr::kPi;
using hr::Rgb;
using hr::Vec3;

/// Solid angle (sr) of the spherical triangle with unit-vector corners a, b, c (Van Oosterom and
/// Strackee 1983); exact up to rounding, for any size.
inline double solidAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
  double num = std::abs(glm::dot(a, glm::cross(b, c)));
  double den = 1.0 + glm::dot(a, b) + glm::dot(b, c) + glm::dot(c, a);
  return 2.0 * std::atan2(num, den);
}

using hr::orthonormalBasis;  // one frame for hosts and extension (hr/types.h)

/// Point j of count at r = 1, as its radius and the cosine and sine of its turn: a caller that spreads
/// many disks over the same count tabulates these once (a sine and a cosine per point per pixel were
/// most of a glossy still's shown light; shown_light.cpp).
struct SunflowerStep {
  double radius, cos, sin;
};
inline SunflowerStep sunflowerStep(int j, int count) {
  const double phi = 2.399963229728653 * j;
  return {std::sqrt((j + 0.5) / count), std::cos(phi), std::sin(phi)};
}
/// A tabulated step's point on the disk of radius r (the same bits as the overload below).
inline Vec3 sunflowerPoint(const Vec3& u, const Vec3& v, double r, const SunflowerStep& s) {
  return (r * s.radius) * (s.cos * u + s.sin * v);
}
/// Point j of count on a sunflower over the disk of radius r spanned by unit u and v: each the
/// centre of an equal share of the disk's area (radius r sqrt((j + 1/2) / count), turned by the
/// golden angle per point). Spreads a sender's disk into directions (reflection.cpp, shown_light.cpp).
inline Vec3 sunflowerPoint(const Vec3& u, const Vec3& v, double r, int j, int count) {
  return sunflowerPoint(u, v, r, sunflowerStep(j, count));
}

/// Barycentric coordinates of a point inside a triangle of the 1->4 hierarchy.
struct Bary {
  double b0, b1, b2;
};

/// One descent step: which child (0-2 at corner 0-2, 3 the inverted middle one) holds the point,
/// and the point's coordinates in that child. Children follow hr::Polygon::subdivide's layout:
/// child k < 3 has corner k and the two midpoints next to it; child 3 is (m12, m20, m01).
inline int descend(Bary& p) {
  if (p.b0 >= 0.5) {
    p = {2.0 * p.b0 - 1.0, 2.0 * p.b1, 2.0 * p.b2};
    return 0;
  }
  if (p.b1 >= 0.5) {
    p = {2.0 * p.b0, 2.0 * p.b1 - 1.0, 2.0 * p.b2};
    return 1;
  }
  if (p.b2 >= 0.5) {
    p = {2.0 * p.b0, 2.0 * p.b1, 2.0 * p.b2 - 1.0};
    return 2;
  }
  p = {1.0 - 2.0 * p.b0, 1.0 - 2.0 * p.b1, 1.0 - 2.0 * p.b2};
  return 3;
}

/// A triangle of the hierarchy as three planar corner points on a polyhedron face.
struct FaceTri {
  Vec3 p[3];
  FaceTri child(int k) const {
    Vec3 m01 = 0.5 * (p[0] + p[1]), m12 = 0.5 * (p[1] + p[2]), m20 = 0.5 * (p[2] + p[0]);
    switch (k) {
      case 0: return {{p[0], m01, m20}};
      case 1: return {{m01, p[1], m12}};
      case 2: return {{m20, m12, p[2]}};
      default: return {{m12, m20, m01}};
    }
  }
  Vec3 dir(int k) const { return glm::normalize(p[k]); }
  Vec3 centreDir() const { return glm::normalize(p[0] + p[1] + p[2]); }
  double solidAngle() const { return glossy::solidAngle(dir(0), dir(1), dir(2)); }
};

/// The octahedron with vertices on the axes: face f (0-7) is the octant with sign bits
/// (x < 0, y < 0, z < 0); its corners are the X, Y and Z axis points of that octant.
inline int octaFace(const Vec3& d) { return (d.x < 0.0 ? 1 : 0) | (d.y < 0.0 ? 2 : 0) | (d.z < 0.0 ? 4 : 0); }
inline FaceTri octaRoot(int f) {
  double sx = (f & 1) ? -1.0 : 1.0, sy = (f & 2) ? -1.0 : 1.0, sz = (f & 4) ? -1.0 : 1.0;
  return {{Vec3(sx, 0, 0), Vec3(0, sy, 0), Vec3(0, 0, sz)}};
}
/// Barycentric coordinates of a direction on its octahedron face: (|x|, |y|, |z|) / (|x|+|y|+|z|).
inline Bary octaBary(const Vec3& d) {
  double s = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
  double inv = s > 0.0 ? 1.0 / s : 0.0;
  return {std::abs(d.x) * inv, std::abs(d.y) * inv, std::abs(d.z) * inv};
}

}  // namespace glossy
