// --basis auto: the rule picks the basis the measured crossovers say (docs/directional.md, "Choosing
// the basis per material"), every basis's options apply to the materials that get it, a cluster over
// materials of different bases keeps one exact sum per basis, and a section mixing bases round-trips
// bit for bit.
#include <gtest/gtest.h>
#include <glossy/basis_rule.h>
#include <glossy/is_options.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "directions.h"
#include "fake_host.h"
#include "../saved_bytes.h"

namespace {

using glossy::Basis;
using glossy::Rgb;
using glossy::Vec3;
using glossy::kPi;
using testhost::NodeId;

glossy::BasisSpec finer() {
  glossy::BasisSpec b = glossy::defaultIsBasis();
  b.haar.maxLevel = 4;
  b.tetraLevel = 4;
  b.shOrder = 12;
  return b;
}

TEST(BasisAuto, PicksTheBasisTheMeasuredCrossoversFavour) {
  // Away from the crossovers of the weighed errors (defaults: the tetrahedron of level 3 for the
  // broadest lobes, SH near n = 10, Haar from about 15; finer settings: the tetrahedron of level 4 up
  // to n ~ 40 and near 100, Haar elsewhere), where they differ by 20 % or more (docs/directional.md).
  struct Row {
    double exponent;
    Basis atDefaults, atFiner;
  };
  const Row rows[] = {
      {2, Basis::Tetra, Basis::Tetra}, {10, Basis::Sh, Basis::Tetra},    {20, Basis::Haar, Basis::Tetra},
      {30, Basis::Haar, Basis::Tetra}, {200, Basis::Haar, Basis::Haar},  {500, Basis::Haar, Basis::Haar},
      {1000, Basis::Haar, Basis::Haar}, {5000, Basis::Haar, Basis::Haar},
  };
  for (const Row& r : rows) {
    EXPECT_EQ(glossy::autoBasis(r.exponent, glossy::defaultIsBasis()), r.atDefaults) << "n = " << r.exponent << ", defaults";
    EXPECT_EQ(glossy::autoBasis(r.exponent, finer()), r.atFiner) << "n = " << r.exponent << ", finer settings";
  }
  EXPECT_EQ(glossy::autoBasis(std::nan(""), glossy::defaultIsBasis()), Basis::Haar);
}

TEST(BasisAuto, TheCostDecidesWhereTheLobesErrorAloneWouldPickTheCostlierBasis) {
  // The glossy sphere's floor (n = 30) at the finer settings: SH-12 projects its lobe best (0.10
  // against the tetrahedron's 0.12) but costs a solve 6.5 times as much, and the sphere's study
  // showed the tetrahedron's image better in a fifth of the time (docs/directional.md).
  glossy::AutoChoice c = glossy::autoChoice(30.0, finer());
  const auto sh = std::size_t(Basis::Sh), tetra = std::size_t(Basis::Tetra);
  EXPECT_LT(c.l2RelError[sh], c.l2RelError[tetra]);
  EXPECT_GT(c.cost[sh], 4.0 * c.cost[tetra]);
  EXPECT_EQ(c.basis, Basis::Tetra);
}

TEST(BasisAuto, TheChoiceIsTheSmallestWeighedErrorAndRepeats) {
  for (double n : {3.0, 17.0, 40.0, 150.0, 2000.0}) {
    glossy::AutoChoice c = glossy::autoChoice(n, finer()), again = glossy::autoChoice(n, finer());
    const auto k = std::size_t(c.basis);
    for (std::size_t b = 0; b < 3; ++b) {
      EXPECT_LE(c.merit[k], c.merit[b]) << "n = " << n;
      EXPECT_NEAR(c.merit[b], std::max(c.l2RelError[b], glossy::kErrorFloor) * std::pow(c.cost[b], glossy::kCostExponent), 1e-12)
          << "n = " << n;
      EXPECT_GT(c.coefficients[b], 0u) << "n = " << n;
      EXPECT_TRUE(std::isfinite(c.l2RelError[b]));
      EXPECT_EQ(c.l2RelError[b], again.l2RelError[b]) << "deterministic";
    }
  }
}

TEST(BasisAuto, EveryBasisOptionAppliesToTheMaterialsThatGetIt) {
  auto ext = testhost::configured({{"basis", "auto"}, {"tetra-level", "4"}, {"sh-order", "12"}, {"dir-max-level", "4"}});
  const glossy::BasisSpec& b = ext->basis();
  EXPECT_TRUE(b.automatic);
  EXPECT_EQ(b.tetraLevel, 4);
  EXPECT_EQ(b.shOrder, 12);
  EXPECT_EQ(b.haar.maxLevel, 4);
  // Checked against the finer settings' table (docs/directional.md): n = 30 gets the tetrahedron of
  // level 4 (weighed errors 0.52 against Haar's 0.67 and SH's 0.69).
  testhost::FakeHost host;
  std::uint32_t m = host.addMaterial(testhost::glossyMaterial(30.0));
  NodeId leaf = host.addElement(Vec3(0.0), Vec3(0, 0, 1), 1.0, m);
  host.addCluster({leaf});
  ext->attach(host);
  EXPECT_EQ(ext->materialBasis(m), Basis::Tetra);
  ext->reflect(leaf, std::vector<hr::IncidentSample>{testhost::sample(testhost::around(Vec3(0, 0, 1), 0.5), Rgb(1.0))});
  ASSERT_NE(ext->light(leaf), nullptr);
  const auto* t = std::get_if<glossy::TetraDistribution>(&ext->light(leaf)->dist);
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->level(), 4);
}

/// A broad (n = 10: spherical harmonics) and a sharp (n = 1000: Haar) glossy floor side by side, each
/// split into four leaves, and a diffuse wall, under one cluster; lit, reflected and pulled once.
struct Mixed {
  testhost::FakeHost host;
  NodeId broad, sharp, wall, cluster;
  std::uint32_t broadMaterial, sharpMaterial;
  std::unique_ptr<glossy::IlluminationSamples> ext = testhost::configured({{"basis", "auto"}});
  Mixed() {
    broadMaterial = host.addMaterial(testhost::glossyMaterial(10.0));
    sharpMaterial = host.addMaterial(testhost::glossyMaterial(1000.0));
    std::uint32_t d = host.addMaterial(testhost::diffuseMaterial());
    broad = host.addElement(Vec3(-1, 0, 0), Vec3(0, 0, 1), 1.0, broadMaterial);
    sharp = host.addElement(Vec3(1, 0, 0), Vec3(0, 0, 1), 1.0, sharpMaterial);
    host.split(broad);
    host.split(sharp);
    wall = host.addElement(Vec3(0, 1, 0.5), Vec3(0, -1, 0), 0.5, d);
    cluster = host.addCluster({broad, sharp, wall});
    ext->attach(host);
    std::mt19937_64 g(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (NodeId leaf : host.simulatedLeaves(*ext)) {
      std::vector<hr::IncidentSample> s;
      for (int k = 0; k < 3; ++k) s.push_back(testhost::sample(testhost::around(Vec3(0, 0, 1), 1.2 * u(g), 2 * kPi * u(g)), Rgb(u(g), 1.0, 0.5)));
      ext->reflect(leaf, s);
    }
    host.pullAll(*ext);
  }
};

TEST(BasisAuto, AClusterOverTwoBasesKeepsOneExactSumPerBasis) {
  Mixed m;
  ASSERT_EQ(m.ext->materialBasis(m.broadMaterial), Basis::Sh);
  ASSERT_EQ(m.ext->materialBasis(m.sharpMaterial), Basis::Haar);
  const auto* c = m.ext->light(m.cluster);
  ASSERT_NE(c, nullptr);
  ASSERT_EQ(c->more.size(), 1u) << "one part per basis";
  EXPECT_TRUE(std::holds_alternative<glossy::HaarDistribution>(c->dist));
  EXPECT_TRUE(std::holds_alternative<glossy::ShDistribution>(c->more[0].dist));
  // Power: the cluster holds what its two floors hold (Haar sums are exact up to float rounding,
  // spherical harmonics coefficient by coefficient).
  Rgb children = m.ext->light(m.broad)->totalPower() + m.ext->light(m.sharp)->totalPower();
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c->totalPower()[k] / children[k], 1.0, 1e-5) << "channel " << k;
  // The broad part's intensity is its floor's exactly; the cluster's is the sum of its parts'.
  std::mt19937_64 g(3);
  for (int k = 0; k < 200; ++k) {
    Vec3 d = testdirs::sphere(g);
    Rgb sh = glossy::eval(c->more[0].dist, d), floor = glossy::eval(m.ext->light(m.broad)->dist, d);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(sh[ch], floor[ch], 1e-9 * (1.0 + std::abs(floor[ch])));
    Rgb all = m.ext->intensity(m.cluster, d);
    Rgb parts = glm::max(Rgb(0.0), glossy::eval(c->dist, c->frame.toLocal(d))) + glm::max(Rgb(0.0), sh);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(all[ch], parts[ch], 1e-9 * (1.0 + parts[ch]));
  }
  // A bound over a cone is never below the intensity in it.
  for (int k = 0; k < 200; ++k) {
    Vec3 d = testdirs::sphere(g);
    Rgb bound = m.ext->intensityBound(m.cluster, d, std::cos(0.2)), at = m.ext->intensity(m.cluster, d);
    for (int ch = 0; ch < 3; ++ch) EXPECT_GE(bound[ch], at[ch] * (1.0 - 1e-6));
  }
  double others = 0.0;
  for (const auto& e : m.ext->stats())
    if (e.name == "distribution_parts_in_other_bases") others = e.value;
  EXPECT_GE(others, 1.0);
}

TEST(BasisAuto, AMixedSectionRoundTripsBitIdentically) {
  Mixed m;
  const std::string bytes = testutil::savedBytes(*m.ext);
  testhost::FakeHost saved = m.host.elementsOnly();
  glossy::IlluminationSamples loaded;  // default options: the section states its bases
  loaded.load(bytes, saved);
  EXPECT_TRUE(loaded.basis().automatic);
  EXPECT_EQ(loaded.materialBasis(m.broadMaterial), Basis::Sh);
  EXPECT_EQ(loaded.materialBasis(m.sharpMaterial), Basis::Haar);
  EXPECT_EQ(testutil::savedBytes(loaded), bytes) << "saving again gives the same bytes";
  std::mt19937_64 g(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (NodeId leaf : saved.simulatedLeaves(loaded)) {
    EXPECT_EQ(loaded.light(leaf)->dist.index(), m.ext->light(leaf)->dist.index());
    EXPECT_EQ(loaded.reflectedPower(leaf), m.ext->reflectedPower(leaf));
    for (int k = 0; k < 100; ++k) {
      Vec3 d = testdirs::sphere(g), a, b;
      EXPECT_EQ(loaded.intensity(leaf, d), m.ext->intensity(leaf, d));
      EXPECT_EQ(loaded.radiance(leaf, d), m.ext->radiance(leaf, d));
      double u1 = u(g), u2 = u(g);
      EXPECT_EQ(loaded.sampleExitant(leaf, u1, u2, a), m.ext->sampleExitant(leaf, u1, u2, b));
      EXPECT_EQ(a, b);
    }
  }
  std::printf("mixed section: %zu bytes\n", bytes.size());
}

}  // namespace
