// Transfer kernels. Element-to-element links use the exact point-to-polygon form factor (Lambert's
// contour integral, with the sender clipped to the receiver's horizon): it is bounded by 1 for
// touching elements and its sum over a tiling of the surroundings is exactly 1, which keeps closed
// scenes energy-conserving. Links with a cluster end use intensity over a bounded squared distance.
#pragma once
#include <hr/polygon.h>

namespace hr {

/// Form factor from a differential area at x (unit normal n) to the front side of polygon p whose
/// unit normal is pn. Zero when x is behind p or p is below x's horizon. Always within [0, 1].
double pointPolygonFormFactor(const Vec3& x, const Vec3& n, const Polygon& p, const Vec3& pn);

/// Area average over polygon r (unit normal rn) of the point form factor to s: Gauss-Legendre with
/// order x order points on the bilinear map of a quad or the collapsed map of a triangle. Order 4 is
/// within 2e-6 of the closed form for perpendicular squares sharing an edge, the hardest case.
double meanFormFactor(const Polygon& r, const Vec3& rn, const Polygon& s, const Vec3& sn, int order = 4);

/// Closed forms used by tests and documentation: unit squares facing each other at distance d, and
/// perpendicular unit squares sharing an edge.
double parallelSquaresFormFactor(double side, double distance);
double perpendicularSquaresFormFactor();

}  // namespace hr
