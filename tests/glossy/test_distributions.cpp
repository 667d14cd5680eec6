// The three directional bases against exact facts: the integral of a projected constant (4 pi c),
// cell solid angles that tile the sphere, vertex and triangle counts, band-limited functions that
// spherical harmonics must reproduce, linearity of add and scale, and serialization round trips.
#include <glossy/distribution.h>
#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include "directions.h"

namespace {

using glossy::Rgb;
using glossy::Vec3;
using glossy::kPi;

Vec3 randomDir(std::mt19937_64& g) { return testdirs::sphere(g); }

/// A smooth, positive test function with a bump near +x+y.
Rgb bumpy(const Vec3& d) {
  double b = std::exp(8.0 * (glm::dot(d, glm::normalize(Vec3(1, 1, 0.3))) - 1.0));
  return {1.0 + 3.0 * b, 0.5 + d.z * 0.25, 2.0 * b};
}

TEST(Distributions, ConstantProjectsToFourPiTimesTheConstant) {
  const Rgb c(0.3, 1.7, 2.5);
  auto f = [&](const Vec3&) { return c; };
  auto check = [&](const Rgb& got, const std::string& what) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k] / (4.0 * kPi * c[k]), 1.0, 1e-6) << what << " channel " << k;
  };
  for (int m : {0, 2, 5}) {
    glossy::HaarOptions o;
    o.minLevel = m;
    check(glossy::HaarDistribution::project(f, o).integral(), "haar min level " + std::to_string(m));
  }
  for (int n = 0; n <= 6; ++n) check(glossy::TetraDistribution::project(f, n).integral(), "tetra level " + std::to_string(n));
  for (int L : {1, 4, 16}) check(glossy::ShDistribution::project(f, L).integral(), "sh order " + std::to_string(L));
}

TEST(Distributions, CellsTileTheSphere) {
  for (int level : {0, 3, 6}) {
    glossy::HaarOptions o;
    o.minLevel = o.maxLevel = level;
    auto d = glossy::HaarDistribution::project([](const Vec3&) { return Rgb(1.0); }, o);
    double sum = 0.0;
    std::size_t cells = 0;
    d.visitLeaves([&](const glossy::FaceTri& t, int, const Rgb&, std::uint64_t) { sum += t.solidAngle(), ++cells; });
    EXPECT_EQ(cells, std::size_t(8) << (2 * level));
    EXPECT_NEAR(sum / (4.0 * kPi), 1.0, 1e-6) << "haar level " << level;
  }
  for (int n = 0; n <= 6; ++n) {
    const auto& m = glossy::TetraMesh::get(n);
    EXPECT_EQ(m.triangleCount(), std::size_t(1) << (2 * (n + 1))) << "4^(n+1) triangles";
    EXPECT_EQ(m.vertexCount(), 2 * (std::size_t(1) << (2 * n)) + 2) << "2*4^n + 2 vertices";
    double cells = 0.0, weights = 0.0;
    for (std::size_t t = 0; t < m.triangleCount(); ++t) cells += m.cellSolidAngle(t);
    for (std::size_t i = 0; i < m.vertexCount(); ++i) weights += m.weight(i);
    EXPECT_NEAR(cells / (4.0 * kPi), 1.0, 1e-6) << "tetra level " << n;
    EXPECT_NEAR(weights / (4.0 * kPi), 1.0, 1e-6) << "tetra level " << n;
  }
}

TEST(Distributions, HaarEvalFindsTheCellThatHoldsTheDirection) {
  // Brute force: the leaf whose spherical triangle contains d (all three edge planes agree).
  glossy::HaarOptions o;
  o.minLevel = 2;
  o.maxLevel = 6;
  o.eps = 0.05;
  auto d = glossy::HaarDistribution::project(bumpy, o);
  std::mt19937_64 g(5);
  for (int k = 0; k < 2000; ++k) {
    Vec3 v = randomDir(g);
    Rgb found(-1.0);
    int hits = 0;
    d.visitLeaves([&](const glossy::FaceTri& t, int, const Rgb& value, std::uint64_t) {
      Vec3 a = t.dir(0), b = t.dir(1), c = t.dir(2);
      double s = glm::dot(glm::cross(a, b), c) > 0.0 ? 1.0 : -1.0;
      if (s * glm::dot(glm::cross(a, b), v) >= -1e-12 && s * glm::dot(glm::cross(b, c), v) >= -1e-12 &&
          s * glm::dot(glm::cross(c, a), v) >= -1e-12)
        found = value, ++hits;
    });
    ASSERT_GE(hits, 1);
    if (hits == 1) {
      EXPECT_EQ(d.eval(v), found) << "direction " << v.x << "," << v.y << "," << v.z;
    }
  }
}

TEST(Distributions, ApproximationConvergesAtTheRightOrder) {
  // On a smooth function, piecewise constant (Haar) error halves per level (first order) and
  // piecewise linear (tetra) error quarters (second order). Checked between levels 4 and 6 on the
  // maximum error over 4000 directions: ratios above 3 (Haar, two levels) and 10 (tetra).
  std::mt19937_64 g(9);
  std::vector<Vec3> dirs(4000);
  for (auto& v : dirs) v = randomDir(g);
  auto maxErr = [&](const auto& dist) {
    double e = 0.0;
    for (const Vec3& v : dirs) e = std::max(e, glm::length(dist.eval(v) - bumpy(v)));
    return e;
  };
  auto haar = [&](int level) {
    glossy::HaarOptions o;
    o.minLevel = o.maxLevel = level;
    return maxErr(glossy::HaarDistribution::project(bumpy, o));
  };
  auto tetra = [&](int level) { return maxErr(glossy::TetraDistribution::project(bumpy, level)); };
  double h4 = haar(4), h6 = haar(6), t4 = tetra(4), t6 = tetra(6);
  EXPECT_GT(h4 / h6, 3.0) << h4 << " -> " << h6;
  EXPECT_GT(t4 / t6, 10.0) << t4 << " -> " << t6;
}

TEST(Distributions, SphericalHarmonicsReproduceBandLimitedFunctions) {
  // A polynomial of degree 2 in (x, y, z) lies in bands 0-2: order 3 must reproduce it.
  auto f = [](const Vec3& d) { return Rgb(1.0 + 2.0 * d.x + 3.0 * d.x * d.y - d.z * d.z, d.y, 0.5); };
  auto s = glossy::ShDistribution::project(f, 3);
  std::mt19937_64 g(3);
  for (int k = 0; k < 500; ++k) {
    Vec3 v = randomDir(g);
    Rgb e = s.eval(v) - f(v);
    EXPECT_LT(glm::length(e), 1e-5);
  }
  // Orthonormality through the quadrature: projecting basis function 7 gives coefficient 1 there.
  auto one = [&](const Vec3& d) {
    double y[16];
    s.basis(d, y);
    return Rgb(y[7]);
  };
  auto p = glossy::ShDistribution::project(one, 4);
  Vec3 v = glm::normalize(Vec3(0.3, -0.5, 0.8));
  double y[16];
  p.basis(v, y);
  EXPECT_NEAR(p.eval(v).x, y[7], 1e-6);
}

template <class D>
void checkLinearity(const D& a, const D& b) {
  D sum = a;
  sum.add(b);
  D twice = a;
  twice.scale(2.0);
  std::mt19937_64 g(11);
  for (int k = 0; k < 1000; ++k) {
    Vec3 v = randomDir(g);
    Rgb want = a.eval(v) + b.eval(v);
    EXPECT_LT(glm::length(sum.eval(v) - want), 1e-5 * (1.0 + glm::length(want)));
    EXPECT_LT(glm::length(twice.eval(v) - 2.0 * a.eval(v)), 1e-5 * (1.0 + glm::length(a.eval(v))));
  }
  Rgb wantI = a.integral() + b.integral();
  EXPECT_LT(glm::length(sum.integral() - wantI), 1e-5 * glm::length(wantI));
}

TEST(Distributions, AddAndScaleAreLinear) {
  auto other = [](const Vec3& d) { return Rgb(std::exp(20.0 * (d.z - 1.0)), 0.2, 1.0 + d.x); };
  glossy::HaarOptions o;
  o.eps = 0.1;
  o.maxLevel = 6;
  // Different adaptive trees: the sum is their union.
  checkLinearity(glossy::HaarDistribution::project(bumpy, o), glossy::HaarDistribution::project(other, o));
  checkLinearity(glossy::TetraDistribution::project(bumpy, 4), glossy::TetraDistribution::project(other, 4));
  checkLinearity(glossy::ShDistribution::project(bumpy, 6), glossy::ShDistribution::project(other, 6));
}

template <class D>
void checkRoundTrip(const D& d) {
  std::stringstream ss;
  d.serialize(ss);
  std::string bytes = ss.str();
  std::istringstream in(bytes);
  D back = D::deserialize(in);
  std::mt19937_64 g(2);
  for (int k = 0; k < 200; ++k) {
    Vec3 v = randomDir(g);
    EXPECT_EQ(back.eval(v), d.eval(v));
  }
  std::istringstream cut(bytes.substr(0, bytes.size() - 3));
  EXPECT_THROW(D::deserialize(cut), std::runtime_error) << "truncated";
  std::string foreign = bytes;
  foreign[0] ^= 0x55;
  std::istringstream bad(foreign);
  EXPECT_THROW(D::deserialize(bad), std::runtime_error) << "foreign tag";
}

TEST(Distributions, SerializationRoundTripsAndRejectsDamage) {
  glossy::HaarOptions o;
  o.eps = 0.1;
  auto h = glossy::HaarDistribution::project(bumpy, o);
  checkRoundTrip(h);
  checkRoundTrip(glossy::TetraDistribution::project(bumpy, 3));
  checkRoundTrip(glossy::ShDistribution::project(bumpy, 5));
  // A child index pointing back into the tree is damage, not a tree.
  std::stringstream ss;
  h.serialize(ss);
  std::string bytes = ss.str();
  const std::size_t node0 = 8 + 8;  // header, count
  const std::size_t childOfRoot0 = node0 + 12;
  bytes[childOfRoot0] = 3;  // root 0 now claims nodes 3..6 (other roots) as its children
  bytes[childOfRoot0 + 1] = bytes[childOfRoot0 + 2] = bytes[childOfRoot0 + 3] = 0;
  std::istringstream in(bytes);
  EXPECT_THROW(glossy::HaarDistribution::deserialize(in), std::runtime_error);
}

}  // namespace
