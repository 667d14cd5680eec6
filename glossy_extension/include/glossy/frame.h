// The orientation a node's directional distribution is stored in. A planar element keeps its
// distribution in its own frame (normal = +z): the octahedron's equator is then exactly the element's
// horizon, so no Haar cell straddles it, light never leaks below the surface and the upper four faces
// hold all of it. Clusters (and nodes whose children disagree) use the world frame.
#pragma once
#include <glossy/sphere.h>

namespace glossy {

struct Frame {
  Vec3 u{1, 0, 0}, v{0, 1, 0}, n{0, 0, 1};  // orthonormal, right-handed (u x v = n)

  static Frame world() { return {}; }
  /// The frame of a planar node with unit normal n; the same normal always gives the same frame.
  static Frame around(const Vec3& normal) {
    Frame f;
    f.n = glm::normalize(normal);
    orthonormalBasis(normal, f.u, f.v);
    return f;
  }
  Vec3 toLocal(const Vec3& d) const { return {glm::dot(u, d), glm::dot(v, d), glm::dot(n, d)}; }
  Vec3 toWorld(const Vec3& l) const { return l.x * u + l.y * v + l.z * n; }
  /// Same orientation up to rounding (children of a split element carry their parent's normal).
  bool same(const Frame& o) const {
    Vec3 d = glm::abs(u - o.u) + glm::abs(v - o.v) + glm::abs(n - o.n);
    return hr::maxComponent(d) <= 1e-12;
  }
};

}  // namespace glossy
