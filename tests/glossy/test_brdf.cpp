// The modified Phong model against its defining properties: reciprocity, albedo rho_d + rho_s at
// normal incidence (a closed form), never above it elsewhere, finite and non-negative everywhere; and
// the cos^n the lobe integrals use (PhongPower) against std::pow.
#include <glossy/brdf.h>
#include <glossy/phong_power.h>
#include <gtest/gtest.h>

#include <random>

#include "directions.h"

namespace {

using glossy::Rgb;
using glossy::Vec3;
using glossy::kPi;

/// A direction in the upper hemisphere; one in four is grazing (cos theta below 1e-3, down to 1e-9).
Vec3 upper(std::mt19937_64& g) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return testdirs::withCos((g() % 4 == 0) ? std::pow(10.0, -3.0 - 6.0 * u(g)) : u(g), g);
}

TEST(Phong, ReciprocalOverRandomPairsIncludingGrazing) {
  std::mt19937_64 g(1);
  const Vec3 n(0, 0, 1);
  for (int k = 0; k < 100000; ++k) {
    glossy::ModifiedPhong b{Rgb(0.2), Rgb(0.7), std::pow(10.0, 4.0 * double(k % 1000) / 1000.0)};
    Vec3 wi = upper(g), wo = upper(g);
    Rgb f1 = glossy::eval(b, wi, wo, n), f2 = glossy::eval(b, wo, wi, n);
    ASSERT_TRUE(std::isfinite(f1.x) && f1.x >= 0.0);
    ASSERT_NEAR(f1.x, f2.x, 1e-6 * std::max(1.0, f1.x)) << "n = " << b.exponent;
  }
}

TEST(Phong, AlbedoAtNormalIncidenceIsDiffusePlusSpecular) {
  const Vec3 n(0, 0, 1);
  for (double e : {1.0, 10.0, 100.0, 1000.0}) {
    glossy::Brdf b = glossy::ModifiedPhong{Rgb(0.25), Rgb(0.7), e};
    EXPECT_NEAR(glossy::albedo(b, n, n).x, 0.95, 1e-3) << "n = " << e;
  }
}

TEST(Phong, AlbedoNeverExceedsDiffusePlusSpecular) {
  // Off normal incidence part of the lobe falls below the horizon and cos(theta_o) < cos(alpha):
  // the albedo drops. Tolerance 1e-4: the reference quadrature's own error.
  const Vec3 n(0, 0, 1);
  for (double e : {1.0, 10.0, 100.0, 1000.0}) {
    glossy::Brdf b = glossy::ModifiedPhong{Rgb(0.1), Rgb(0.9), e};
    double prev = 2.0;
    for (double deg = 0.0; deg < 90.0; deg += 7.5) {
      double t = deg * kPi / 180.0;
      double a = glossy::albedo(b, Vec3(std::sin(t), 0, std::cos(t)), n, 256).x;
      EXPECT_LE(a, 1.0 + 1e-4) << "n = " << e << " at " << deg << " deg";
      EXPECT_LE(a, prev + 1e-4) << "albedo falls with incidence";
      EXPECT_GE(a, 0.1 - 1e-4) << "the diffuse part stays";
      prev = a;
    }
  }
}

TEST(Phong, FiniteAndNonNegativeEverywhere) {
  const Vec3 n(0, 0, 1);
  std::mt19937_64 g(4);
  for (double e : {0.0, 1e-3, 1.0, 1e4, 1e5}) {
    glossy::ModifiedPhong b{Rgb(0.3), Rgb(0.6), e};
    for (int k = 0; k < 20000; ++k) {
      Vec3 wi = upper(g), wo = (k % 3 == 0) ? glossy::mirror(wi, n) : upper(g);
      if (k % 7 == 0) wo.z = -wo.z;  // below the surface: zero
      Rgb f = glossy::eval(b, wi, wo, n);
      ASSERT_TRUE(std::isfinite(f.x) && f.x >= 0.0) << "n = " << e;
      if (wo.z < 0.0) {
        ASSERT_EQ(f.x, 0.0);
      }
    }
    // Exactly grazing and exactly mirrored.
    Vec3 graze(1, 0, 0);
    EXPECT_EQ(glossy::eval(b, graze, graze, n).x, 0.0);
    Vec3 wi = glm::normalize(Vec3(0.3, 0, 1));
    Rgb peak = glossy::eval(b, wi, glossy::mirror(wi, n), n);
    EXPECT_TRUE(std::isfinite(peak.x));
    EXPECT_NEAR(peak.x, 0.3 / kPi + 0.6 * (e + 2.0) / (2.0 * kPi), 1e-9 * (1.0 + e));
  }
}

TEST(Lambert, AlbedoIsRho) {
  const Vec3 n(0, 0, 1);
  glossy::Brdf b = glossy::Lambert{Rgb(0.4, 0.5, 0.6)};
  Rgb a = glossy::albedo(b, glm::normalize(Vec3(1, 0, 1)), n);
  EXPECT_NEAR(a.y, 0.5, 1e-12);
  EXPECT_EQ(glossy::eval(b, n, n, n).y, 0.5 / kPi);
}

TEST(PhongPower, MatchesPowAndTakesAnIntegerARoundingAwayAsThatInteger) {
  // MGF's rs 0.1 gives 2 / 0.1^2 - 2 = 197.99999999999997: the squaring chain alone (no exp2/log2).
  const double mgf = 2.0 / (0.1 * 0.1) - 2.0;
  ASSERT_NE(mgf, 198.0);
  struct Case {
    double n;
    std::uint32_t integer;
    double fraction;
  };
  for (const Case& c : {Case{mgf, 198u, 0.0}, Case{198.0, 198u, 0.0}, Case{197.5, 197u, 0.5}, Case{198.000001, 198u, 1e-6},
                        Case{0.25, 0u, 0.25}, Case{7.0, 7u, 0.0}}) {
    const glossy::PhongPower p(c.n);
    EXPECT_EQ(p.integerPart(), c.integer) << c.n;
    EXPECT_NEAR(p.fraction(), c.fraction, 1e-9) << c.n;
    EXPECT_EQ(p.exponent(), c.n);
    double worst = 0.0;
    for (int k = 1; k <= 2000; ++k) {
      const double cosine = double(k) / 2000.0;
      const double want = cosine > p.cutoff() ? std::pow(cosine, c.n) : 0.0;
      if (want > 0.0) worst = std::max(worst, std::abs(p(cosine) - want) / want);
    }
    EXPECT_LT(worst, 1e-10) << c.n;  // 69 * 1e-12 for a snapped exponent, a few ulps otherwise
  }
}

}  // namespace
