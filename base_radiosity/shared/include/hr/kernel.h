// Transfer kernels. Element-to-element links use the exact point-to-polygon form factor (Lambert's
// contour integral, with the sender clipped to the receiver's horizon): it is bounded by 1 for
// touching elements and its sum over a tiling of the surroundings is exactly 1, which keeps closed
// scenes energy-conserving. Links with a cluster end use intensity over a bounded squared distance.
#pragma once
#include <hr/polygon.h>

#include <algorithm>
#include <cmath>

namespace hr {

/// The angle an edge subtends in a contour sum: atan2(y, x) for y >= 0, x and y not both 0, within
/// 2e-14 rad (1.3e-14 measured on 2e7 pairs). libm's atan2 was a quarter of a BRIGHT-like solve
/// (one per edge, some 25 point form factors per link): this one reduces to |u| <= tan(pi/8) with a
/// single division and takes atan(u) / u as a degree-8 polynomial in u^2 (a near-minimax fit).
inline double edgeAngle(double y, double x) {
  constexpr double kTanPi8 = 0.41421356237309504880;
  constexpr double c[9] = {0.9999999999999828,   -0.33333333331029924, 0.19999999628901208,
                           -0.14285691467769254, 0.11110407971488763,  -0.09078669255367892,
                           0.07565574701271902,  -0.05881115266500173, 0.030757603969338368};
  const double ax = std::abs(x), lo = std::min(y, ax), hi = std::max(y, ax);
  double u, base;
  if (lo <= kTanPi8 * hi) u = lo / hi, base = 0.0;
  else u = (lo - hi) / (lo + hi), base = 0.25 * kPi;  // atan(t) = pi/4 + atan((t - 1) / (t + 1))
  // Estrin's scheme: three dependent steps where Horner's takes eight.
  const double z = u * u, z2 = z * z, z4 = z2 * z2;
  const double q = ((c[0] + c[1] * z) + (c[2] + c[3] * z) * z2) + ((c[4] + c[5] * z) + (c[6] + c[7] * z) * z2) * z4 +
                   c[8] * (z4 * z4);
  double a = base + u * q;       // atan(lo / hi), in [0, pi/4]
  if (y > ax) a = 0.5 * kPi - a;  // atan(y / |x|)
  return x < 0.0 ? kPi - a : a;
}

/// Form factor from a differential area at x (unit normal n) to the front side of polygon p whose
/// unit normal is pn. Zero when x is behind p or p is below x's horizon. Always within [0, 1].
double pointPolygonFormFactor(const Vec3& x, const Vec3& n, const Polygon& p, const Vec3& pn);
/// The same with p's centroid() and radius() given, for many points against one polygon (they are
/// five of a call's twelve square roots).
double pointPolygonFormFactor(const Vec3& x, const Vec3& n, const Polygon& p, const Vec3& pn, const Vec3& centroid,
                              double radius);

/// Area average over polygon r (unit normal rn) of the point form factor to s: Gauss-Legendre with
/// order x order points on the bilinear map of a quad or the collapsed map of a triangle. Order 4 is
/// within 2e-6 of the closed form for perpendicular squares sharing an edge, the hardest case.
double meanFormFactor(const Polygon& r, const Vec3& rn, const Polygon& s, const Vec3& sn, int order = 4);

/// Closed forms used by tests and documentation: unit squares facing each other at distance d, and
/// perpendicular unit squares sharing an edge.
double parallelSquaresFormFactor(double side, double distance);
double perpendicularSquaresFormFactor();

}  // namespace hr
