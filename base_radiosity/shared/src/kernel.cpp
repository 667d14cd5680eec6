// Point-to-polygon form factor (Lambert / Hottel contour formula) with horizon clipping, and the
// closed forms the tests compare against.
#include <hr/kernel.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace hr {

double pointPolygonFormFactor(const Vec3& x, const Vec3& n, const Polygon& p, const Vec3& pn, const Vec3& centroid,
                              double radius) {
  // The sender radiates from its front only: x must lie in front of p's plane.
  if (glm::dot(x - p.v[0], pn) <= 0.0) return 0.0;
  // Clip p to the half-space above x's tangent plane (Sutherland-Hodgman, at most 5 vertices).
  Vec3 in[5], out[5];
  int m = 0;
  double scale = radius + glm::length(centroid - x);
  double tol = 1e-12 * scale;
  for (int i = 0; i < p.n; ++i) {
    const Vec3& a = p.v[i];
    const Vec3& b = p.v[(i + 1) % p.n];
    double da = glm::dot(a - x, n), db = glm::dot(b - x, n);
    if (da > tol) out[m++] = a;
    if ((da > tol) != (db > tol)) {
      double t = (tol - da) / (db - da);
      if (m < 5) out[m++] = a + t * (b - a);
    }
  }
  if (m < 3) return 0.0;
  double len[5];
  for (int i = 0; i < m; ++i) in[i] = out[i] - x, len[i] = glm::length(in[i]);
  double sum = 0.0;
  for (int i = 0; i < m; ++i) {
    const int j = (i + 1) % m;
    if (len[i] == 0.0 || len[j] == 0.0) continue;
    Vec3 c = glm::cross(in[i], in[j]);
    double lc = glm::length(c);
    if (lc == 0.0) continue;
    double theta = edgeAngle(lc, glm::dot(in[i], in[j]));
    sum += theta * glm::dot(c / lc, n);
  }
  // Vertices run counter-clockwise seen from the front of p, i.e. clockwise seen from x: the
  // contour sum is then negative.
  double f = -sum / (2.0 * kPi);
  return glm::clamp(f, 0.0, 1.0);
}

double pointPolygonFormFactor(const Vec3& x, const Vec3& n, const Polygon& p, const Vec3& pn) {
  return pointPolygonFormFactor(x, n, p, pn, p.centroid(), p.radius());
}

namespace {

/// Gauss-Legendre nodes and weights on [0, 1], by Newton's iteration on P_n (done once per order).
struct GaussLegendre {
  std::array<double, 8> x{}, w{};
  explicit GaussLegendre(int n) {
    for (int i = 0; i < n; ++i) {
      double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 1.0;
      for (int it = 0; it < 100; ++it) {
        double p1 = 1.0, p2 = 0.0;
        for (int j = 0; j < n; ++j) {
          double p3 = p2;
          p2 = p1;
          p1 = ((2.0 * j + 1.0) * z * p2 - j * p3) / (j + 1.0);
        }
        dp = n * (z * p1 - p2) / (z * z - 1.0);
        double dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-16) break;
      }
      x[i] = 0.5 * (1.0 - z);
      w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
    }
  }
};

}  // namespace

double meanFormFactor(const Polygon& r, const Vec3& rn, const Polygon& s, const Vec3& sn, int order) {
  static const std::array<GaussLegendre, 9> rules = {GaussLegendre(1), GaussLegendre(1), GaussLegendre(2),
                                                     GaussLegendre(3), GaussLegendre(4), GaussLegendre(5),
                                                     GaussLegendre(6), GaussLegendre(7), GaussLegendre(8)};
  const GaussLegendre& g = rules[std::size_t(std::clamp(order, 1, 8))];
  const int n = std::clamp(order, 1, 8);
  const Vec3 sc = s.centroid();
  const double sr = s.radius();
  double sum = 0.0, wsum = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double u = g.x[i], v = g.x[j], jac;
      Vec3 x;
      if (r.n == 4) {
        Vec3 du = (1.0 - v) * (r.v[1] - r.v[0]) + v * (r.v[2] - r.v[3]);
        Vec3 dv = (1.0 - u) * (r.v[3] - r.v[0]) + u * (r.v[2] - r.v[1]);
        x = (1.0 - u) * (1.0 - v) * r.v[0] + u * (1.0 - v) * r.v[1] + u * v * r.v[2] + (1.0 - u) * v * r.v[3];
        jac = glm::length(glm::cross(du, dv));
      } else {
        // Collapsed square: x = v0 + u (v1 - v0) + u v (v2 - v1), Jacobian proportional to u.
        x = r.v[0] + u * (r.v[1] - r.v[0]) + u * v * (r.v[2] - r.v[1]);
        jac = u;
      }
      double wt = g.w[i] * g.w[j] * jac;
      sum += wt * pointPolygonFormFactor(x, rn, s, sn, sc, sr);
      wsum += wt;
    }
  return wsum > 0.0 ? sum / wsum : 0.0;
}

double parallelSquaresFormFactor(double side, double d) {
  double X = side / d, Y = side / d;
  double x1 = 1.0 + X * X, y1 = 1.0 + Y * Y;
  return 2.0 / (kPi * X * Y) *
         (std::log(std::sqrt(x1 * y1 / (1.0 + X * X + Y * Y))) + X * std::sqrt(y1) * std::atan(X / std::sqrt(y1)) +
          Y * std::sqrt(x1) * std::atan(Y / std::sqrt(x1)) - X * std::atan(X) - Y * std::atan(Y));
}

double perpendicularSquaresFormFactor() {
  // Perpendicular rectangles with a common edge, H = W = 1 (Howell's catalogue, C-14).
  double H = 1.0, W = 1.0;
  double a = W * std::atan(1.0 / W) + H * std::atan(1.0 / H) - std::sqrt(H * H + W * W) * std::atan(1.0 / std::sqrt(H * H + W * W));
  double t1 = (1.0 + W * W) * (1.0 + H * H) / (1.0 + W * W + H * H);
  double t2 = W * W * (1.0 + W * W + H * H) / ((1.0 + W * W) * (W * W + H * H));
  double t3 = H * H * (1.0 + H * H + W * W) / ((1.0 + H * H) * (H * H + W * W));
  return (a + 0.25 * std::log(t1 * std::pow(t2, W * W) * std::pow(t3, H * H))) / (kPi * W);
}

}  // namespace hr
