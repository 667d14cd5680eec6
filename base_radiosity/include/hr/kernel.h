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

/// Closed forms used by tests and documentation: unit squares facing each other at distance d, and
/// perpendicular unit squares sharing an edge.
double parallelSquaresFormFactor(double side, double distance);
double perpendicularSquaresFormFactor();

}  // namespace hr
