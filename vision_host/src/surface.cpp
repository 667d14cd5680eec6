// The parameter maps of the whole primitives (see surface.h). The quadric kinds are evaluated in
// their own frame and carried to the world by an affine map, so a transformed sphere (an ellipsoid
// under non-uniform scale) is still exact; normals go through the inverse transpose.
#include <vision/surface.h>

#include <algorithm>
#include <cmath>

namespace vision {

using hr::kPi;

void Surface::setFrame(const glm::dmat4& m) {
  toWorld = m;
  toLocal = glm::inverse(m);
  normalMatrix = glm::transpose(glm::inverse(glm::dmat3(m)));
}

Vec3 Surface::starBoundary(double u) const {
  // breaks_[i] is the area fraction at boundary vertex i (breaks_.back() == 1 closes the polygon).
  const std::size_t n = pts.size() - 1;
  std::size_t i = std::size_t(std::upper_bound(breaks_.begin(), breaks_.end(), u) - breaks_.begin());
  i = std::clamp<std::size_t>(i, 1, n) - 1;
  double span = breaks_[i + 1] - breaks_[i];
  double t = span > 0.0 ? std::clamp((u - breaks_[i]) / span, 0.0, 1.0) : 0.0;
  return pts[1 + i] + t * (pts[1 + (i + 1) % n] - pts[1 + i]);
}

Vec3 Surface::localPoint(double u, double v) const {
  const double phi = 2.0 * kPi * u;
  switch (kind) {
    case SurfaceKind::Annulus: {
      double r = std::sqrt(std::max(0.0, r0 * r0 + v * (r1 * r1 - r0 * r0)));
      return {r * std::cos(phi), r * std::sin(phi), 0.0};
    }
    case SurfaceKind::Sphere: {
      double z = r0 * (1.0 - 2.0 * v), rho = std::sqrt(std::max(0.0, r0 * r0 - z * z));
      return {rho * std::cos(phi), rho * std::sin(phi), z};
    }
    case SurfaceKind::Frustum: {
      // Equal-area in v: the lateral area up to radius r grows with r^2 - r0^2 (with z for a cylinder).
      double r = r0, z = v * height;
      if (std::abs(r1 - r0) > 1e-12 * std::max(r0, r1)) {
        r = std::sqrt(std::max(0.0, r0 * r0 + v * (r1 * r1 - r0 * r0)));
        z = height * (r - r0) / (r1 - r0);
      }
      return {r * std::cos(phi), r * std::sin(phi), z};
    }
    default: return Vec3(0.0);
  }
}

Vec3 Surface::localNormal(double u, double v) const {
  const double phi = 2.0 * kPi * u;
  switch (kind) {
    case SurfaceKind::Annulus: return {0.0, 0.0, 1.0};
    case SurfaceKind::Sphere: return localPoint(u, v) / r0;
    case SurfaceKind::Frustum: {
      Vec3 n(height * std::cos(phi), height * std::sin(phi), r0 - r1);
      return n / glm::length(n);
    }
    default: return {0.0, 0.0, 1.0};
  }
}

Vec3 Surface::point(double u, double v) const {
  switch (kind) {
    case SurfaceKind::Bilinear:
      return (1.0 - u) * (1.0 - v) * pts[0] + u * (1.0 - v) * pts[1] + u * v * pts[2] + (1.0 - u) * v * pts[3];
    case SurfaceKind::Star: return pts[0] + std::sqrt(std::max(0.0, v)) * (starBoundary(u) - pts[0]);
    default: return Vec3(toWorld * glm::dvec4(localPoint(u, v), 1.0));
  }
}

Vec3 Surface::normal(double u, double v) const {
  if (kind == SurfaceKind::Bilinear || kind == SurfaceKind::Star) return flatNormal;
  Vec3 n = glm::normalize(normalMatrix * localNormal(u, v));
  return inward ? -n : n;
}

double Surface::jacobian(double u, double v) const {
  switch (kind) {
    case SurfaceKind::Bilinear: {
      Vec3 pu = (1.0 - v) * (pts[1] - pts[0]) + v * (pts[2] - pts[3]);
      Vec3 pv = (1.0 - u) * (pts[3] - pts[0]) + u * (pts[2] - pts[1]);
      return glm::length(glm::cross(pu, pv));
    }
    case SurfaceKind::Star: return r0;  // the polygon's area: the map is equal-area
    default: break;
  }
  // Local area element (constant: the maps are equal-area) times the area scale of the affine map
  // for a surface of local normal n: |det L| |L^-T n|.
  double local = 0.0;
  switch (kind) {
    case SurfaceKind::Annulus: local = kPi * (r1 * r1 - r0 * r0); break;
    case SurfaceKind::Sphere: local = 4.0 * kPi * r0 * r0; break;
    default: local = kPi * (r0 + r1) * std::sqrt(height * height + (r1 - r0) * (r1 - r0)); break;
  }
  const glm::dmat3 L(toWorld);
  return local * std::abs(glm::determinant(L)) * glm::length(normalMatrix * localNormal(u, v));
}

}  // namespace vision
