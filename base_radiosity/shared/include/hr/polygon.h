// Planar convex polygons with 3 or 4 vertices: the shape of every patch and element. Small inline
// helpers (area, normal, sampling, point location) used by the hierarchy, the kernels and the renderer.
#pragma once
#include <hr/types.h>

#include <array>
#include <utility>

namespace hr {

struct Polygon {
  std::array<Vec3, 4> v{};
  int n = 3;  // 3 or 4

  Vec3 centroid() const {
    Vec3 c(0.0);
    for (int i = 0; i < n; ++i) c += v[i];
    return c / double(n);
  }
  /// Area vector (normal times area), exact for planar polygons.
  Vec3 areaVector() const {
    Vec3 a(0.0);
    for (int i = 1; i + 1 < n; ++i) a += glm::cross(v[i] - v[0], v[i + 1] - v[0]);
    return 0.5 * a;
  }
  double area() const { return glm::length(areaVector()); }
  /// Circumscribed radius about the centroid: the polygon's size seen from afar.
  double radius() const {
    Vec3 c = centroid();
    double r = 0.0;
    for (int i = 0; i < n; ++i) r = glm::max(r, glm::length(v[i] - c));
    return r;
  }
  /// Mean squared distance of the polygon's points from its area centroid, m^2 (polar moment / area):
  /// a triangle's is (a^2 + b^2 + c^2) / 36 for sides a, b, c; a quad adds its two triangles'.
  double spread2() const {
    if (n == 3) return triSpread2(v[0], v[1], v[2]);
    const auto [a0, a1] = twiceTriangleAreas();
    if (a0 + a1 <= 0.0) return 0.0;
    Vec3 g0 = (v[0] + v[1] + v[2]) / 3.0, g1 = (v[0] + v[2] + v[3]) / 3.0, g = (a0 * g0 + a1 * g1) / (a0 + a1);
    return (a0 * (triSpread2(v[0], v[1], v[2]) + glm::dot(g0 - g, g0 - g)) +
            a1 * (triSpread2(v[0], v[2], v[3]) + glm::dot(g1 - g, g1 - g))) / (a0 + a1);
  }
  static double triSpread2(const Vec3& a, const Vec3& b, const Vec3& c) {
    return (glm::dot(b - a, b - a) + glm::dot(c - b, c - b) + glm::dot(a - c, a - c)) / 36.0;
  }
  /// The area covariance about the area centroid, m^2 (a sender's shape, hr/sender_shape.h): exact,
  /// from each triangle's integral of x x^T, (A / 12)(sum of v v^T + s s^T) with s the vertex sum,
  /// taken about v0 so that far-off polygons keep their digits.
  glm::dmat3 areaMoments() const {
    glm::dmat3 m(0.0);
    Vec3 first(0.0);
    double total = 0.0;
    const auto [t0, t1] = twiceTriangleAreas();  // the fan's two triangles (a triangle's is the first)
    for (int i = 1; i + 1 < n; ++i) {
      const Vec3 b = v[i] - v[0], c = v[i + 1] - v[0], s = b + c;
      const double a = 0.5 * (i == 1 ? t0 : t1);
      m += (a / 12.0) * (glm::outerProduct(b, b) + glm::outerProduct(c, c) + glm::outerProduct(s, s));
      first += (a / 3.0) * s;
      total += a;
    }
    if (!(total > 0.0)) return glm::dmat3(0.0);
    const Vec3 g = first / total;
    return m / total - glm::outerProduct(g, g);
  }
  /// The area centroid (the vertex mean for triangles; differs from it for non-parallelogram quads).
  Vec3 areaCentroid() const {
    if (n == 3) return centroid();
    const auto [a0, a1] = twiceTriangleAreas();
    if (a0 + a1 <= 0.0) return centroid();
    return (a0 * (v[0] + v[1] + v[2]) + a1 * (v[0] + v[2] + v[3])) / (3.0 * (a0 + a1));
  }
  /// Maps (u,v) in [0,1)^2 to a point, uniformly in area: triangles by the square-root warp, quads by
  /// splitting into two triangles chosen in proportion to their areas.
  Vec3 sample(double u, double w) const { return sample(u, w, firstShare()); }
  /// The same with firstShare() given: a link's shadow rays draw many points of one polygon, and the
  /// two cross products and lengths per point were a fifth of a link's own work.
  Vec3 sample(double u, double w, double p) const {
    if (n == 3) return sampleTri(v[0], v[1], v[2], u, w);
    if (u < p) return sampleTri(v[0], v[1], v[2], u / glm::max(p, 1e-300), w);
    return sampleTri(v[0], v[2], v[3], (u - p) / glm::max(1.0 - p, 1e-300), w);
  }
  /// The share of the area that sample() draws in the first triangle (v0 v1 v2): 1 for a triangle.
  double firstShare() const {
    if (n == 3) return 1.0;
    const auto [a0, a1] = twiceTriangleAreas();
    return a0 / glm::max(a0 + a1, 1e-300);
  }
  /// Twice the areas of a quad's two triangles, (v0 v1 v2) and (v0 v2 v3).
  std::pair<double, double> twiceTriangleAreas() const {
    return {glm::length(glm::cross(v[1] - v[0], v[2] - v[0])),
            glm::length(glm::cross(v[2] - v[0], v[3] - v[0]))};
  }
  static Vec3 sampleTri(const Vec3& a, const Vec3& b, const Vec3& c, double u, double w) {
    double s = std::sqrt(glm::clamp(u, 0.0, 1.0));
    return a * (1.0 - s) + b * (s * (1.0 - w)) + c * (s * w);
  }
  /// Splits into the four children of the quadtree (1 -> 4 for triangles and quads alike).
  std::array<Polygon, 4> subdivide() const {
    std::array<Polygon, 4> ch;
    if (n == 3) {
      Vec3 m01 = 0.5 * (v[0] + v[1]), m12 = 0.5 * (v[1] + v[2]), m20 = 0.5 * (v[2] + v[0]);
      ch[0] = {{v[0], m01, m20, Vec3(0.0)}, 3};
      ch[1] = {{m01, v[1], m12, Vec3(0.0)}, 3};
      ch[2] = {{m20, m12, v[2], Vec3(0.0)}, 3};
      ch[3] = {{m12, m20, m01, Vec3(0.0)}, 3};
    } else {
      Vec3 m01 = 0.5 * (v[0] + v[1]), m12 = 0.5 * (v[1] + v[2]), m23 = 0.5 * (v[2] + v[3]),
           m30 = 0.5 * (v[3] + v[0]), c = 0.25 * (v[0] + v[1] + v[2] + v[3]);
      ch[0] = {{v[0], m01, c, m30}, 4};
      ch[1] = {{m01, v[1], m12, c}, 4};
      ch[2] = {{c, m12, v[2], m23}, 4};
      ch[3] = {{m30, c, m23, v[3]}, 4};
    }
    return ch;
  }
  /// Smallest signed distance (in units of the polygon's own size) of p to the inside of the edges,
  /// measured in the plane with normal nrm: >= 0 inside. Used to find the child that holds a point.
  double insideness(const Vec3& p, const Vec3& nrm) const {
    double m = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i) {
      const Vec3& a = v[i];
      const Vec3& b = v[(i + 1) % n];
      Vec3 e = b - a;
      double len = glm::length(e);
      if (len == 0.0) continue;
      m = glm::min(m, glm::dot(glm::cross(e, p - a), nrm) / len);
    }
    return m;
  }
  /// Whether p lies strictly inside every edge (in the plane with normal nrm): insideness > 0 by its
  /// signs alone, without the per-edge lengths that only ranking points outside needs.
  bool strictlyInside(const Vec3& p, const Vec3& nrm) const {
    for (int i = 0; i < n; ++i) {
      const Vec3& a = v[i];
      const Vec3 e = v[(i + 1) % n] - a;
      if (glm::dot(e, e) == 0.0) continue;  // as insideness skips a zero-length edge
      if (!(glm::dot(glm::cross(e, p - a), nrm) > 0.0)) return false;
    }
    return true;
  }
};

}  // namespace hr
