// A flat sender's shape (hr/sender_shape.h) from a polygon's area moments (Polygon::areaMoments),
// against closed forms: a triangle's covariance, a rectangle's sides in any plane and any turn, and a
// square's sides, which its moments alone do not name.
#include <hr/polygon.h>
#include <hr/sender_shape.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

using hr::Vec3;

/// The polygon with corners c + x u + y w for the given (x, y), in the plane spanned by unit u, w.
hr::Polygon inPlane(const Vec3& c, const Vec3& u, const Vec3& w, std::initializer_list<hr::Vec2> xy) {
  hr::Polygon p;
  p.n = int(xy.size());
  int k = 0;
  for (const hr::Vec2& q : xy) p.v[std::size_t(k++)] = c + q.x * u + q.y * w;
  return p;
}

TEST(SenderShape, ATrianglesMomentsAreItsClosedForm) {
  // The right triangle (0,0), (1,0), (0,1) far from the origin: variances 1/18 along each leg and
  // covariance -1/36 (the moments taken about its centroid, whatever its place).
  const Vec3 c(1e3, -2e3, 5e2), u(1, 0, 0), w(0, 1, 0);
  const glm::dmat3 m = inPlane(c, u, w, {{0, 0}, {1, 0}, {0, 1}}).areaMoments();
  EXPECT_NEAR(m[0][0], 1.0 / 18.0, 1e-9);
  EXPECT_NEAR(m[1][1], 1.0 / 18.0, 1e-9);
  EXPECT_NEAR(m[0][1], -1.0 / 36.0, 1e-9);
  EXPECT_NEAR(m[2][2], 0.0, 1e-9);
}

TEST(SenderShape, ARectangleIsItsOwnShapeInAnyPlaneAndTurn) {
  // A 2 x 0.5 m rectangle and a 0.3 m square, in random planes and turns: the half-axis along the
  // long side (for the square: along one of its sides, from the first edge's hint), half-lengths 1 and 0.25 m
  // (0.15 and 0.15), within 1e-9.
  std::mt19937_64 g(7);
  std::normal_distribution<double> z;
  for (int t = 0; t < 50; ++t) {
    const Vec3 n = glm::normalize(Vec3(z(g), z(g), z(g)));
    Vec3 u, w;
    hr::orthonormalBasis(n, u, w);
    const double turn = 6.283185307179586 * (t + 0.5) / 50.0;
    const Vec3 a = std::cos(turn) * u + std::sin(turn) * w, b = glm::cross(n, a), c(z(g), z(g), z(g));
    const hr::Polygon rect = inPlane(c, a, b, {{-1, -0.25}, {1, -0.25}, {1, 0.25}, {-1, 0.25}});
    const hr::SenderRectangle r = hr::rectangleOfMoments(rect.areaMoments(), n, rect.v[1] - rect.v[0]);
    EXPECT_NEAR(std::abs(glm::dot(Vec3(r.axis), a)), 1.0, 1e-6);
    EXPECT_NEAR(glm::length(Vec3(r.axis)), 1.0, 1e-6);
    EXPECT_NEAR(r.halfWidth, 0.25, 1e-6);
    const hr::Polygon square = inPlane(c, a, b, {{-0.15, -0.15}, {0.15, -0.15}, {0.15, 0.15}, {-0.15, 0.15}});
    const hr::SenderRectangle s = hr::rectangleOfMoments(square.areaMoments(), n, square.v[1] - square.v[0]);
    const double along = std::max(std::abs(glm::dot(Vec3(s.axis), a)), std::abs(glm::dot(Vec3(s.axis), b)));
    EXPECT_NEAR(along, 0.15, 1e-6) << "turn " << turn;  // along one side or the other
    EXPECT_NEAR(s.halfWidth, 0.15, 1e-6);
  }
}

TEST(SenderShape, NoShapeWithoutArea) {
  // A degenerate polygon (three points on a line) and a non-finite covariance give no shape.
  const hr::Polygon line = inPlane(Vec3(0.0), Vec3(1, 0, 0), Vec3(0, 1, 0), {{0, 0}, {1, 0}, {2, 0}});
  EXPECT_EQ(hr::rectangleOfMoments(line.areaMoments(), Vec3(0, 0, 1)).axis, glm::vec3(0.0f));
  glm::dmat3 bad(0.0);
  bad[0][0] = std::nan("");
  EXPECT_EQ(hr::rectangleOfMoments(bad, Vec3(0, 0, 1)).axis, glm::vec3(0.0f));
}

}  // namespace
