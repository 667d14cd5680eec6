// Bounded radiosity (Stamminger, Slusallek, Seidel 1997): lower and upper bounds of the point kernel
// cos_s cos_r / r^2 between two nodes from nothing but their bounding boxes and cones of normals.
// The vectors from sender points to receiver points lie in the box R - S; its distance from the
// origin and its farthest corner bound r, the cone around its centre that holds its corners bounds
// the directions, and that cone widened by each node's cone of normals bounds each cosine. The same
// code serves flat and curved elements, clusters and single points.
#include <algorithm>
#include <cmath>
#include <limits>

#include "state.h"

namespace vision::detail {
namespace {

/// Cosine bounds of the angle between a normal in cone (axis, alpha) and a direction in cone
/// (dirAxis, beta); both clamped at zero (the far side sends and receives nothing).
void cosineBounds(const Vec3& axis, double alpha, const Vec3& dirAxis, double beta, double& lo, double& hi) {
  if (alpha >= hr::kPi || beta >= hr::kPi) {
    lo = 0.0, hi = 1.0;
    return;
  }
  double gamma = std::acos(std::clamp(glm::dot(axis, dirAxis), -1.0, 1.0));
  double near = std::max(0.0, gamma - alpha - beta), far = std::min(hr::kPi, gamma + alpha + beta);
  hi = std::max(0.0, std::cos(near));
  lo = std::max(0.0, std::cos(far));
}

/// A node whose normals all agree sends only into the open half-space in front of its lowest point
/// and receives only from there: two coplanar walls never exchange light, whatever their boxes say.
bool behind(const Geometry& a, const Geometry& b) {
  if (a.coneAngle > 1e-6) return false;  // (merged cones of parallel panels carry rounding)
  const Vec3& n = a.coneAxis;
  double aMin = std::numeric_limits<double>::infinity(), bMax = -aMin;
  for (int k = 0; k < 8; ++k) {
    Vec3 ca((k & 1) ? a.box.hi.x : a.box.lo.x, (k & 2) ? a.box.hi.y : a.box.lo.y, (k & 4) ? a.box.hi.z : a.box.lo.z);
    Vec3 cb((k & 1) ? b.box.hi.x : b.box.lo.x, (k & 2) ? b.box.hi.y : b.box.lo.y, (k & 4) ? b.box.hi.z : b.box.lo.z);
    aMin = std::min(aMin, glm::dot(n, ca));
    bMax = std::max(bMax, glm::dot(n, cb));
  }
  double size = a.box.diagonal() + b.box.diagonal();
  return bMax <= aMin + 1e-9 * size;
}

}  // namespace

Geometry pointGeometry(const Vec3& x, const Vec3& n) {
  Geometry g;
  g.center = x, g.normal = n, g.coneAxis = n;
  g.box.grow(x);
  return g;
}

KernelBounds kernelBounds(const Geometry& s, const Geometry& r) {
  KernelBounds kb;
  if (behind(s, r) || behind(r, s)) return kb;
  const Vec3 lo = r.box.lo - s.box.hi, hi = r.box.hi - s.box.lo;  // sender -> receiver vectors
  Vec3 near(0.0), far(0.0);
  bool contains = true;
  for (int c = 0; c < 3; ++c) {
    near[c] = lo[c] > 0.0 ? lo[c] : hi[c] < 0.0 ? hi[c] : 0.0;
    far[c] = std::max(std::abs(lo[c]), std::abs(hi[c]));
    contains = contains && lo[c] <= 0.0 && hi[c] >= 0.0;
  }
  if (contains) {
    kb.overlap = true;
    kb.kmax = std::numeric_limits<double>::infinity();
    return kb;
  }
  const double rmin2 = glm::dot(near, near), rmax2 = glm::dot(far, far);
  const Vec3 mid = 0.5 * (lo + hi);
  const double ml = glm::length(mid);
  Vec3 axis = ml > 0.0 ? mid / ml : Vec3(0, 0, 1);
  double beta = ml > 0.0 ? 0.0 : hr::kPi;
  for (int k = 0; k < 8 && beta < hr::kPi; ++k) {
    Vec3 c((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
    double l = glm::length(c);
    double ang = l > 0.0 ? std::acos(std::clamp(glm::dot(axis, c) / l, -1.0, 1.0)) : hr::kPi;
    // Past 90 degrees the cone around the axis is no longer convex: it bounds nothing.
    beta = ang >= 0.5 * hr::kPi ? hr::kPi : std::max(beta, ang);
  }
  double sLo, sHi, rLo, rHi;
  cosineBounds(s.coneAxis, s.coneAngle, axis, beta, sLo, sHi);
  cosineBounds(r.coneAxis, r.coneAngle, -axis, beta, rLo, rHi);
  kb.kmax = sHi * rHi / rmin2;
  kb.kmin = sLo * rLo / rmax2;
  kb.axis = axis, kb.beta = beta, kb.rLo = rLo, kb.rHi = rHi, kb.rmin2 = rmin2, kb.rmax2 = rmax2;
  return kb;
}

}  // namespace vision::detail
