// Spherical caps, polygon clipping by great circles, Arvo's triangle sampling and the edge formula
// for projected solid angles. Every routine keeps its result on the sphere and finite for
// degenerate (tiny or sliver) input, because the cells it is used on go down to a fraction of a degree.
#include <glossy/spherical_geometry.h>

#include <algorithm>

namespace glossy {

Cap Cap::cone(const Vec3& axis, double cosHalfAngle) {
  Cap c;
  double len = glm::length(axis);
  if (!(len > 0.0) || !std::isfinite(len) || !(cosHalfAngle > -1.0)) return c;  // whole sphere
  c.centre = axis / len;
  c.cosR = std::min(cosHalfAngle, 1.0);
  c.sinR = std::sqrt(std::max(0.0, 1.0 - c.cosR * c.cosR));
  return c;
}

Cap Cap::around(const FaceTri& t) {
  Cap c;
  c.centre = t.centreDir();
  c.cosR = 1.0;
  for (int k = 0; k < 3; ++k) c.cosR = std::min(c.cosR, glm::dot(c.centre, t.dir(k)));
  c.sinR = std::sqrt(std::max(0.0, 1.0 - c.cosR * c.cosR));
  return c;
}

bool Cap::overlaps(const Cap& o) const {
  if (whole() || o.whole()) return true;
  // The angular radii add up to pi or more exactly when cos r2 <= -cos r1.
  if (o.cosR <= -cosR) return true;
  double cosSum = cosR * o.cosR - sinR * o.sinR;  // cos(r1 + r2)
  return glm::dot(centre, o.centre) >= cosSum - 1e-9;
}

bool meets(const Cap& cone, const FaceTri& t) {
  if (cone.whole()) return true;
  Vec3 v[3] = {t.dir(0), t.dir(1), t.dir(2)}, inward[3];
  insideNormals(v[0], v[1], v[2], inward);
  const Vec3& c = cone.centre;
  if (glm::dot(c, inward[0]) >= 0.0 && glm::dot(c, inward[1]) >= 0.0 && glm::dot(c, inward[2]) >= 0.0) return true;
  const double threshold = cone.cosR - 1e-9;
  for (int k = 0; k < 3; ++k) {
    const Vec3 &a = v[k], &b = v[(k + 1) % 3];
    // The arc's closest direction to the axis: its foot on the great circle if that lies on the arc,
    // otherwise the nearer end.
    double best = std::max(glm::dot(c, a), glm::dot(c, b));
    Vec3 m = glm::cross(a, b);
    double len = glm::length(m);
    if (len > 0.0) {
      m /= len;
      Vec3 p = c - glm::dot(c, m) * m;
      if (glm::dot(glm::cross(a, p), m) >= 0.0 && glm::dot(glm::cross(p, b), m) >= 0.0) best = std::max(best, glm::length(p));
    }
    if (best >= threshold) return true;
  }
  return false;
}

void SphericalPolygon::clip(const Vec3& m) {
  if (n == 0) return;
  Vec3 out[8];
  int k = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 &p = v[i], &q = v[(i + 1) % n];
    double dp = glm::dot(p, m), dq = glm::dot(q, m);
    if (dp >= 0.0 && k < 8) out[k++] = p;
    if ((dp >= 0.0) != (dq >= 0.0) && k < 8) {
      // The point of the arc p-q on the great circle: a positive combination of p and q.
      Vec3 x = dp >= 0.0 ? dp * q - dq * p : dq * p - dp * q;
      double len = glm::length(x);
      if (len > 0.0) out[k++] = x / len;
    }
  }
  n = k < 3 ? 0 : k;
  std::copy(out, out + n, v);
}

double SphericalPolygon::area() const {
  double s = 0.0;
  for (int i = 1; i + 1 < n; ++i) s += solidAngle(v[0], v[i], v[i + 1]);
  return s;
}

void insideNormals(const Vec3& a, const Vec3& b, const Vec3& c, Vec3 out[3]) {
  const Vec3* p[3] = {&a, &b, &c};
  for (int k = 0; k < 3; ++k) {
    Vec3 m = glm::cross(*p[k], *p[(k + 1) % 3]);
    if (glm::dot(m, *p[(k + 2) % 3]) < 0.0) m = -m;
    out[k] = m;
  }
}

namespace {

/// The part of a orthogonal to unit b, normalised; falls back to any perpendicular when a ~ b.
Vec3 perpendicular(const Vec3& a, const Vec3& b) {
  Vec3 p = a - glm::dot(a, b) * b;
  double len = glm::length(p);
  if (len > 1e-300) return p / len;
  Vec3 u, v;
  orthonormalBasis(b, u, v);
  return u;
}

}  // namespace

Vec3 sampleTriangle(const Vec3& A, const Vec3& B, const Vec3& C, double u1, double u2) {
  // Angle alpha at A between the great circles AB and AC, and the side c = |AB|.
  Vec3 nab = glm::cross(A, B), nac = glm::cross(A, C);
  double lab = glm::length(nab), lac = glm::length(nac);
  double area = solidAngle(A, B, C);
  if (!(lab > 0.0) || !(lac > 0.0) || !(area > 0.0)) return glm::normalize(A + B + C);
  double cosAlpha = glm::clamp(glm::dot(nab, nac) / (lab * lac), -1.0, 1.0);
  double sinAlpha = std::sqrt(std::max(0.0, 1.0 - cosAlpha * cosAlpha));
  double cosC = glm::clamp(glm::dot(A, B), -1.0, 1.0);
  // Choose the sub-triangle A B C' of area u1 * area: find C' on the arc AC.
  double a1 = u1 * area;
  double s = std::sin(a1 - std::acos(cosAlpha)), t = std::cos(a1 - std::acos(cosAlpha));
  double u = t - cosAlpha, v = s + sinAlpha * cosC;
  double den = (v * s + u * t) * sinAlpha;
  double q = den != 0.0 ? ((v * t - u * s) * cosAlpha - v) / den : 1.0;
  q = glm::clamp(q, -1.0, 1.0);
  Vec3 Cp = q * A + std::sqrt(std::max(0.0, 1.0 - q * q)) * perpendicular(C, A);
  // Then a point on the arc B C' with the right density.
  double z = 1.0 - u2 * (1.0 - glm::dot(Cp, B));
  z = glm::clamp(z, -1.0, 1.0);
  Vec3 P = z * B + std::sqrt(std::max(0.0, 1.0 - z * z)) * perpendicular(Cp, B);
  return hr::allFinite(P) ? glm::normalize(P) : glm::normalize(A + B + C);
}

double projectedSolidAngle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n) {
  const Vec3* p[3] = {&a, &b, &c};
  // Orient the edges counter-clockwise seen from outside so the sum is positive above the plane.
  bool ccw = glm::dot(a, glm::cross(b, c)) >= 0.0;
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const Vec3& x = *p[k];
    const Vec3& y = ccw ? *p[(k + 1) % 3] : *p[(k + 2) % 3];
    Vec3 g = glm::cross(x, y);
    double len = glm::length(g);
    if (!(len > 0.0)) continue;
    double angle = std::atan2(len, glm::dot(x, y));
    sum += angle * glm::dot(g / len, n);
  }
  return std::max(0.0, 0.5 * sum);
}

}  // namespace glossy
