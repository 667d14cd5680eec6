// Point-to-polygon form factor against closed forms and the sum rule of a closed enclosure.
#include <gtest/gtest.h>
#include <hr/kernel.h>
#include <hr/rng.h>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace {

hr::Polygon quad(hr::Vec3 a, hr::Vec3 b, hr::Vec3 c, hr::Vec3 d) { return {{a, b, c, d}, 4}; }

TEST(Kernel, EnclosureSumsToOne) {
  // From any interior point of one face of a cube, the other five faces subtend everything: sum F = 1.
  using hr::Vec3;
  std::vector<hr::Polygon> faces = {
      quad({1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}),  // x=1 facing -x
      quad({0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}),  // y=1 facing -y
      quad({0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}) ,  // y=0 facing +y
      quad({0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}),  // z=1 facing -z
      quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}),  // z=0 facing +z
  };
  hr::Rng rng(1, 2);
  for (int t = 0; t < 1000; ++t) {
    Vec3 x(0.0, rng.uniform(), rng.uniform());
    double sum = 0.0;
    for (const auto& f : faces) sum += hr::pointPolygonFormFactor(x, {1, 0, 0}, f, glm::normalize(f.areaVector()));
    ASSERT_NEAR(sum, 1.0, 1e-9) << "at " << x.y << "," << x.z;
  }
}

TEST(Kernel, DiskOnAxisClosedForm) {
  // Differential area to a coaxial square approximated by checking against a square's exact
  // point form factor: F = (2/pi) [a/sqrt(1+a^2) atan(a/sqrt(1+a^2))]*2 for half-side a at distance 1.
  double a = 0.5;
  double expected = 8.0 * (1.0 / (2.0 * hr::kPi)) * (a / std::sqrt(1 + a * a)) * std::atan(a / std::sqrt(1 + a * a));
  auto q = quad({-a, -a, 1}, {-a, a, 1}, {a, a, 1}, {a, -a, 1});
  double f = hr::pointPolygonFormFactor({0, 0, 0}, {0, 0, 1}, q, glm::normalize(q.areaVector()));
  EXPECT_NEAR(f, expected, 1e-12);
}

TEST(Kernel, EdgeAngleIsAtan2) {
  // The contour sum's own atan2 (hr::edgeAngle) against libm's, over angles in every octant and
  // magnitudes over twelve decades, and at the axes; the bar is its stated 2e-14 rad.
  hr::Rng rng(3, 4);
  double worst = 0.0;
  for (int t = 0; t < 200000; ++t) {
    const double y = rng.uniform() * std::pow(10.0, 12.0 * rng.uniform() - 6.0);
    const double x = (2.0 * rng.uniform() - 1.0) * std::pow(10.0, 12.0 * rng.uniform() - 6.0);
    worst = std::max(worst, std::abs(hr::edgeAngle(y, x) - std::atan2(y, x)));
  }
  for (double y : {0.0, 1e-300, 1.0})
    for (double x : {-1.0, -1e-300, 0.0, 1e-300, 1.0})
      if (y != 0.0 || x != 0.0) worst = std::max(worst, std::abs(hr::edgeAngle(y, x) - std::atan2(y, x)));
  EXPECT_LT(worst, 2e-14);
}

TEST(Kernel, FewQuadraturePointsSufficeFarApart) {
  // The BRIGHT-like host integrates far links with order 2 (radii summing to under 0.2 of the
  // distance) or 3 (under 0.3): unit squares facing each other 10 and 5 apart (0.14 and 0.28)
  // against Howell's closed form, within the errors that choice was measured at (1.9e-5, 2.8e-6).
  auto recv = quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
  auto n = [](const hr::Polygon& p) { return glm::normalize(p.areaVector()); };
  for (auto [d, order, bar] : {std::tuple{10.0, 2, 1.9e-5}, std::tuple{5.0, 3, 2.8e-6}}) {
    auto above = quad({0, 0, d}, {0, 1, d}, {1, 1, d}, {1, 0, d});
    EXPECT_NEAR(hr::meanFormFactor(recv, n(recv), above, n(above), order) / hr::parallelSquaresFormFactor(1, d), 1.0, bar)
        << "d " << d << ", order " << order;
  }
}

TEST(Kernel, BackFacingAndBelowHorizonAreZero) {
  auto q = quad({0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1});  // faces +z: x below it sees its back
  EXPECT_EQ(hr::pointPolygonFormFactor({0.5, 0.5, 0}, {0, 0, 1}, q, glm::normalize(q.areaVector())), 0.0);
  auto below = quad({0, 0, -1}, {0, 1, -1}, {1, 1, -1}, {1, 0, -1});
  EXPECT_EQ(hr::pointPolygonFormFactor({0.5, 0.5, 0}, {0, 0, 1}, below, glm::normalize(below.areaVector())), 0.0);
}

TEST(Kernel, TouchingStaysBounded) {
  // Receiver point almost on the shared edge of perpendicular squares: F -> 1/2, never above 1.
  auto q = quad({0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1});
  for (double eps : {1e-3, 1e-6, 1e-9, 1e-12}) {
    double f = hr::pointPolygonFormFactor({eps, 0.5, 0}, {0, 0, 1}, q, glm::normalize(q.areaVector()));
    EXPECT_TRUE(std::isfinite(f));
    EXPECT_LE(f, 0.5 + 1e-9);
    EXPECT_GE(f, 0.0);
  }
}

TEST(Kernel, MeanFormFactorMatchesClosedForms) {
  // Area-averaged form factors by Gauss-Legendre over the receiver against Howell's closed forms,
  // including the hardest case (a shared edge, where the point form factor climbs steeply).
  auto recv = quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});  // faces +z
  auto above = quad({0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1});  // faces -z
  auto side = quad({0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1});   // faces +x, shares the edge x = 0
  auto n = [](const hr::Polygon& p) { return glm::normalize(p.areaVector()); };
  EXPECT_NEAR(hr::meanFormFactor(recv, n(recv), above, n(above), 4) / hr::parallelSquaresFormFactor(1, 1), 1.0, 1e-4);
  EXPECT_NEAR(hr::meanFormFactor(recv, n(recv), side, n(side), 4) / hr::perpendicularSquaresFormFactor(), 1.0, 1e-5);
  // A triangle receiver (the collapsed map) covering half the square: the two halves sum to the whole.
  hr::Polygon t1{{hr::Vec3(0, 0, 0), hr::Vec3(1, 0, 0), hr::Vec3(1, 1, 0), hr::Vec3(0)}, 3};
  hr::Polygon t2{{hr::Vec3(0, 0, 0), hr::Vec3(1, 1, 0), hr::Vec3(0, 1, 0), hr::Vec3(0)}, 3};
  double half = 0.5 * (hr::meanFormFactor(t1, n(t1), side, n(side), 6) + hr::meanFormFactor(t2, n(t2), side, n(side), 6));
  EXPECT_NEAR(half / hr::perpendicularSquaresFormFactor(), 1.0, 1e-3);
}

}  // namespace
