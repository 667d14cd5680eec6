// Shooting (--iteration shoot) in the diffuse core: the same solution as gathering, the closed-form
// furnace, energy conservation, an unshot power that falls with every pass, honest non-convergence at
// albedo 0.99, and the same answer for any thread count.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "helpers.h"

namespace {

hr::SolverOptions shooting(hr::SolverOptions o) {
  o.iteration = hr::Iteration::Shoot;
  return o;
}

std::string furnace(double rho) {
  const std::string r = std::to_string(rho);
  return R"({ "materials": { "g": { "diffuse": [)" + r + "," + r + "," + r + R"(], "emission": [1,1,1] } },
  "objects": [ { "type": "box", "material": "g", "min": [0,0,0], "max": [1,1,1], "facing": "inward" } ] })";
}

/// Largest relative difference, over objects and channels, of the element-area-weighted mean radiosity.
double worstObjectDifference(const testutil::Solved& a, const testutil::Solved& b) {
  double worst = 0.0;
  for (std::uint32_t o = 0; o < a.scene.objects.size(); ++o) {
    hr::Rgb ma = a.meanRadiosity(o), mb = b.meanRadiosity(o);
    for (int c = 0; c < 3; ++c)
      if (mb[c] > 0.0) worst = std::max(worst, std::abs(ma[c] / mb[c] - 1.0));
  }
  return worst;
}

// Both schemes converge to the same answer as the threshold falls, but not at the same rate:
// shooters are patches, so shooting never sends through cluster senders (intensity tables, far-field
// model) as gathering does, and each scheme's discretisation error is its own. Worst object and
// channel, |shoot / gather - 1|, seeds 1-3 (2026-12-05): 0.27 / 0.40 / 0.41 % at the scene's eps
// 2e-4 (1.09 / 0.31 / 0.49 % before the lamp, 1 mm under the ceiling, covered the ceiling's rim
// around it: coplanar.h, kNearGap), 0.20 / 0.14 / 0.17 % at 1e-4, 0.36 / 0.19 / 0.11 % at 5e-5,
// 0.05 % at 2e-5 (seed 2), where this test ran until then. 1e-4 keeps a margin for every seed tried
// at a fifth of the time.
TEST(Shooting, AgreesWithGatheringOnTheCornellBox) {
  hr::SolverOptions o = testutil::options(1e-4, 7);
  o.tolerance = 1e-5;
  o.seed = 2;
  auto g = testutil::solveText(hr::kDefaultSceneJson, o);
  auto s = testutil::solveText(hr::kDefaultSceneJson, shooting(o));
  ASSERT_TRUE(g.stats.converged);
  ASSERT_TRUE(s.stats.converged);
  double worst = worstObjectDifference(s, g);
  std::printf("Cornell box, eps 1e-4: worst object mean shoot/gather - 1 = %.3g (%d passes, %d iterations)\n", worst,
              s.stats.iterations, g.stats.iterations);
  EXPECT_LT(worst, 0.005);
  for (const auto* r : {&g, &s})
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR((r->stats.absorbedW[c] + r->stats.escapedW[c]) / r->stats.emittedW[c], 1.0, 0.01) << "channel " << c;
}

/// The floor's (object 0, the plane y = 0 over [0, 2]^2) leaf radiosity (green, W/m^2) at an n x n
/// grid of cell centres; -1 where the leaf is wholly covered (under a block).
std::vector<double> floorGrid(const testutil::Solved& r, int n) {
  std::vector<double> v(std::size_t(n) * n, -1.0);
  for (std::uint32_t i = 0; i < r.h->elements().size(); ++i) {
    const auto& e = r.h->element(i);
    if (!e.leaf() || r.h->patches()[e.patch].object != 0 || !(r.solver->openFraction()[i] > 0.0f)) continue;
    double x0 = 1e9, x1 = -1e9, z0 = 1e9, z1 = -1e9;
    for (int k = 0; k < e.poly.n; ++k)
      x0 = std::min(x0, e.poly.v[k].x), x1 = std::max(x1, e.poly.v[k].x), z0 = std::min(z0, e.poly.v[k].z),
      z1 = std::max(z1, e.poly.v[k].z);
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        const double x = 2.0 * (a + 0.5) / n, z = 2.0 * (b + 0.5) / n;
        if (x >= x0 && x < x1 && z >= z0 && z < z1) v[std::size_t(a) * n + b] = r.solver->radiosity()[i][1];
      }
  }
  return v;
}

// The oracle must refine a lamp's shadows the same way whichever links reach the lamp first.
// Gathering reaches it from the root cluster's self-link after its links to the walls have split it;
// shooting reaches it from the lamp alone. The shadow term held only leaf senders to it, so the floor
// took it under shooting and not under gathering: the floor's direct light stopped at elements four
// times as wide, and the two schemes' first passes (direct light alone) were 9.4 % apart over the
// floor (RMS over a 128 x 128 grid, relative to the mean; seen failing), 1.2 % with emitters held to
// it too.
TEST(Shooting, ALampsShadowsAreRefinedAlikeByBothSchemes) {
  hr::SolverOptions o = testutil::options(2e-4, 6);
  o.maxIterations = 1;
  auto g = testutil::solveText(hr::kDefaultSceneJson, o);
  auto s = testutil::solveText(hr::kDefaultSceneJson, shooting(o));
  const int n = 128;
  const std::vector<double> a = floorGrid(g, n), b = floorGrid(s, n);
  double sq = 0.0, mean = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] < 0.0 || b[i] < 0.0) continue;
    sq += (a[i] - b[i]) * (a[i] - b[i]), mean += a[i], ++count;
  }
  ASSERT_GT(count, n * n / 2);
  mean /= count;
  const double rms = std::sqrt(sq / count) / mean;
  std::printf("Cornell box floor, direct light: gathering vs shooting %.4f (RMS / mean)\n", rms);
  EXPECT_LT(rms, 0.04);
}

TEST(Shooting, AgreesWithGatheringAndTheClosedFormInTheFurnace) {
  for (double rho : {0.5, 0.9}) {
    hr::SolverOptions o = testutil::options(4e-4, 4);
    o.maxIterations = 400;
    o.tolerance = 1e-5;
    auto g = testutil::solveText(furnace(rho), o);
    auto s = testutil::solveText(furnace(rho), shooting(o));
    ASSERT_TRUE(s.stats.converged) << "rho " << rho;
    EXPECT_LT(worstObjectDifference(s, g), 0.005) << "rho " << rho;
    const double expected = hr::kPi / (1.0 - rho);
    double worst = 0.0;
    for (std::size_t i = 0; i < s.h->elements().size(); ++i)
      if (s.h->element(static_cast<std::uint32_t>(i)).leaf())
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(s.solver->radiosity()[i][c] / expected - 1.0));
    std::printf("furnace rho %.1f: worst leaf %.3g off pi Le/(1-rho), %d passes, absorbed/emitted - 1 = %.3g\n", rho,
                worst, s.stats.iterations, s.stats.absorbedW.y / s.stats.emittedW.y - 1.0);
    EXPECT_LT(worst, 0.01) << "every element within 1 % of pi Le / (1 - rho)";
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.stats.absorbedW[c] / s.stats.emittedW[c], 1.0, 0.01);
  }
}

TEST(Shooting, OpenCornellBoxBalances) {
  auto s = testutil::solveText(hr::kDefaultSceneJson, shooting(testutil::options(2e-4, 6)));
  ASSERT_TRUE(s.stats.converged);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR((s.stats.absorbedW[c] + s.stats.escapedW[c]) / s.stats.emittedW[c], 1.0, 0.01) << "channel " << c;
  EXPECT_EQ(s.stats.iteration, hr::Iteration::Shoot);
  EXPECT_LE(s.stats.unshotW, 1e-4 * hr::luminance(s.stats.emittedW));
}

// A lamp facing away from everything: its first shot's link is refined away (nothing in front of
// it), so it keeps none. The pass's link count wrapped below zero there and the solve threw
// "vector::reserve"; now every watt escapes and the solve converges with no link stored.
TEST(Shooting, ALampFacingAwayFromEverythingShootsIntoTheVoid) {
  const char* scene = R"({ "materials": { "w": { "diffuse": [0.5,0.5,0.5] }, "l": { "emission": [10,10,10] } },
    "objects": [ { "type": "quad", "material": "w", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]] },
                 { "type": "quad", "material": "l", "vertices": [[-0.1,1,-0.1],[-0.1,1,0.1],[0.1,1,0.1],[0.1,1,-0.1]] } ] })";
  hr::SolveStats st;
  ASSERT_NO_THROW(st = testutil::solveText(scene, shooting(testutil::options(1e-3, 6))).stats);
  EXPECT_TRUE(st.converged);
  EXPECT_EQ(st.links, 0u);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(st.escapedW[c], st.emittedW[c], 1e-9 * st.emittedW[c]) << "channel " << c;
}

// A pass sends its shooters' unshot power P and adds back at most rho P, so with rho < 1 the unshot
// power left must fall with every pass (links that created energy would show here).
TEST(Shooting, UnshotPowerFallsWithEveryPass) {
  auto s = testutil::solveText(hr::kDefaultSceneJson, shooting(testutil::options(2e-4, 6)));
  ASSERT_GE(s.stats.history.size(), 3u);
  for (std::size_t i = 1; i < s.stats.history.size(); ++i) {
    EXPECT_LT(s.stats.history[i].residualW, s.stats.history[i - 1].residualW) << "pass " << i + 1;
    EXPECT_GT(s.stats.history[i].shooters, 0u);
  }
  // The first pass shoots the light alone (nothing else has light yet).
  EXPECT_EQ(s.stats.history[0].shooters, 1u);
}

// Albedo 0.99 in a closed box: about 900 sweeps would be needed for 1e-4. With 30 passes the solver
// must stop, say it did not converge, and report the unshot power left.
TEST(Shooting, HighAlbedoStopsAtTheIterationLimitAndSaysSo) {
  hr::SolverOptions o = shooting(testutil::options(1e-3, 3));
  o.maxIterations = 30;
  auto s = testutil::solveText(furnace(0.99), o);
  EXPECT_FALSE(s.stats.converged);
  EXPECT_EQ(s.stats.iterations, 30);
  EXPECT_GT(s.stats.unshotW, o.tolerance * hr::luminance(s.stats.emittedW));
  EXPECT_EQ(s.stats.unshotW, s.stats.history.back().residualW);
  std::string out;
  int status = testutil::runCli("solve " + std::string(GHR_SOURCE_DIR) +
                                    "/scenes/furnace_cube.json --iteration shoot --max-iterations 5 --quiet -o " +
                                    testing::TempDir() + "/shoot_limit",
                                out);
  EXPECT_EQ(WEXITSTATUS(status), 3) << out;
}

TEST(Shooting, ProgressNamesTheUnshotPowerLeft) {
  std::string out;
  int status = testutil::runCli("solve " + std::string(GHR_SOURCE_DIR) +
                                    "/scenes/furnace_cube.json --iteration shoot --max-iterations 3 -o " +
                                    testing::TempDir() + "/shoot_progress",
                                out);
  EXPECT_EQ(WEXITSTATUS(status), 3);
  EXPECT_NE(out.find("pass 3:"), std::string::npos) << out;
  EXPECT_NE(out.find("NOT CONVERGED after 3 passes"), std::string::npos) << out;
  EXPECT_NE(out.find("unshot power left"), std::string::npos) << out;
}

TEST(Determinism, ShootingSameSeedSameAnswerForAnyThreadCount) {
  auto run = [](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    hr::SolverOptions o = shooting(testutil::options(1e-3, 6));
    o.seed = 7;
    return testutil::solveText(hr::kDefaultSceneJson, o);
  };
  auto one = run(1), two = run(2);
  const auto &a = one.solver->radiosity(), &b = two.solver->radiosity();
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(hr::Rgb)), 0) << "radiosity, bit for bit";
  EXPECT_EQ(one.stats.links, two.stats.links);
  EXPECT_EQ(one.stats.rays, two.stats.rays);
  EXPECT_EQ(one.stats.iterations, two.stats.iterations);
  EXPECT_EQ(one.stats.unshotW, two.stats.unshotW);
}

}  // namespace

namespace {

/// Two closed unit rooms 10 m apart along x, each with a lamp under its ceiling and a sphere.
std::string twoRoomsWithSpheres() {
  auto room = [](double x) {
    const std::string lo = std::to_string(x), hi = std::to_string(x + 1.0), l0 = std::to_string(x + 0.4),
                      l1 = std::to_string(x + 0.6);
    return R"({ "type": "box", "material": "w", "min": [)" + lo + R"(,0,0], "max": [)" + hi +
           R"(,1,1], "facing": "inward" }, { "type": "quad", "material": "e", "vertices": [[)" + l0 + ",0.99,0.4],[" + l1 +
           ",0.99,0.4],[" + l1 + ",0.99,0.6],[" + l0 + R"(,0.99,0.6]] }, { "type": "sphere", "material": "w", "center": [)" +
           std::to_string(x + 0.5) + ",0.3,0.5], \"radius\": 0.15 }";
  };
  return R"({ "materials": { "w": { "diffuse": [0.6,0.6,0.6] }, "e": { "emission": [5,5,5] } },
    "objects": [ )" + room(0.0) + ", " + room(10.0) + " ] }";
}

// Two closed rooms 10 m apart, each with its own lamp and a sphere: a pass of one shooter lights one
// room, and its push/pull visits that room alone (the other is as the last pass left it). The answer
// must be the one a push over everything gives, bit for bit; a subtree skipped that should have been
// visited (light that reached a cluster over the sphere's patches, say) would change it.
TEST(Shooting, APassPushesOnlyTheRoomItLitAndChangesNothingElse) {
  const std::string json = twoRoomsWithSpheres();
  // A coarse threshold: the lamp lights each sphere's many patches through links to their clusters.
  hr::SolverOptions o = shooting(testutil::options(2e-3, 5));
  o.shootFraction = 1.0;  // the strongest patch alone: each pass lights one room
  o.maxIterations = 60;
  auto pruned = testutil::solveText(json, o);
  o.testOnlyPushEverything = true;
  auto full = testutil::solveText(json, o);
  const std::size_t P = pruned.h->patches().size();
  std::size_t partial = 0;
  for (const hr::IterationStat& h : pruned.stats.history) {
    EXPECT_GE(h.pushedPatches, 1u);
    if (h.pushedPatches <= P / 2) ++partial;
  }
  for (const hr::IterationStat& h : full.stats.history) EXPECT_EQ(h.pushedPatches, P);
  std::printf("%zu of %zu passes pushed one room or less (%zu patches in all)\n", partial, pruned.stats.history.size(), P);
  EXPECT_GE(partial, pruned.stats.history.size() / 2);
  ASSERT_EQ(pruned.solver->radiosity().size(), full.solver->radiosity().size());
  EXPECT_EQ(std::memcmp(pruned.solver->radiosity().data(), full.solver->radiosity().data(),
                        pruned.solver->radiosity().size() * sizeof(hr::Rgb)),
            0);
}

}  // namespace

namespace {

/// emitted - absorbed - escaped over emitted, green (the energy audit's imbalance).
double imbalance(const testutil::Solved& r) {
  return (r.stats.emittedW.y - r.stats.absorbedW.y - r.stats.escapedW.y) / r.stats.emittedW.y;
}

/// A closed unit room (albedo rho) with a lamp 1 cm under its ceiling and two blocks on its floor;
/// `farBox`: and an empty closed box 10 m away.
std::string roomWithTwoBlocks(double rho, bool farBox) {
  const std::string r = std::to_string(rho);
  return R"({ "materials": { "w": { "diffuse": [)" + r + "," + r + "," + r + R"(] }, "e": { "emission": [5,5,5] } },
    "objects": [
      { "type": "box", "material": "w", "min": [0,0,0], "max": [1,1,1], "facing": "inward" },
      { "type": "quad", "material": "e", "vertices": [[0.4,0.99,0.4],[0.6,0.99,0.4],[0.6,0.99,0.6],[0.4,0.99,0.6]] },
      { "type": "box", "material": "w", "min": [0.3,0,0.3], "max": [0.5,0.4,0.5] },
      { "type": "box", "material": "w", "min": [0.6,0,0.6], "max": [0.8,0.2,0.8] })" +
         std::string(farBox ? R"(,
      { "type": "box", "material": "w", "min": [10,0,0], "max": [11,1,1], "facing": "inward" })" : "") + " ] }";
}

// A closed room of albedo 0.9 with a lamp under its ceiling and two blocks on its floor, at a coarse
// eps 1e-3: light bounces about ten times, so a bias of the links' transfer shows tenfold. The
// oracle used to choose a partly visible inner sender's budget by the very rays that set the link's
// coefficient: links whose four rays all happened to get through were kept (their light
// overstated) and the others split, and the room made 7.6-9.6 % of its light by shooting one patch
// a pass, 1.8-4.5 % by the default shooting and 1.2-1.4 % by gathering (seeds 1-4). Now such a
// kept link is traced again (refine.cpp, seenPartly): within 2.3 % for every scheme and seed.
TEST(Shooting, ABrightRoomNeitherMakesNorLosesLight) {
  const std::string json = roomWithTwoBlocks(0.9, false);
  for (std::uint64_t seed : {1, 2}) {
    hr::SolverOptions o = testutil::options(1e-3, 5);
    o.tolerance = 1e-4;
    o.maxIterations = 4000;
    o.seed = seed;
    auto g = testutil::solveText(json, o);
    ASSERT_TRUE(g.stats.converged);
    std::printf("bright room, seed %llu: gather %+.4f", static_cast<unsigned long long>(seed), imbalance(g));
    EXPECT_LT(std::abs(imbalance(g)), 0.03) << "gather, seed " << seed;
    for (double fraction : {1.0, hr::SolverOptions{}.shootFraction}) {
      o.shootFraction = fraction;
      auto s = testutil::solveText(json, shooting(o));
      ASSERT_TRUE(s.stats.converged) << "fraction " << fraction;
      std::printf(", shoot (fraction %.1f) %+.4f", fraction, imbalance(s));
      EXPECT_LT(std::abs(imbalance(s)), 0.03) << "shoot fraction " << fraction << ", seed " << seed;
    }
    std::printf("\n");
  }
}

// A closed room with a lamp and two blocks, and an empty closed box 10 m away. The cluster tree splits
// patches at the median, so the room's wall at x = 1 shares clusters with the far box; a shooter's
// single link to the root cluster is refined down through them. A wall or floor linked to such a
// cluster (its centre 7 m off, the wall it holds 1 m or less away) was judged by the far-field g^2
// law and gave that wall 0.15-4 % of the light it should get: shooting lost 17.7 % (one shooter a
// pass) and 22 % (default fraction) of the emitted power at eps 1e-3, gathering 2.4 % (the room
// alone: -0.6 %), and room A's objects differed by up to 17 % between the schemes. Now -0.8 %,
// -0.7 % and 0.4 %. Both must balance within 1 %; the objects' bar (3 %, after the fix 1.0 % and
// 2.4 %) is the two schemes' own discretisation difference at this coarse threshold (the Cornell box
// test above: 0.9 % at 2e-4).
TEST(Shooting, ASecondEnclosureLosesNoLight) {
  const std::string json = roomWithTwoBlocks(0.6, true);
  hr::SolverOptions o = testutil::options(1e-3, 5);
  o.tolerance = 1e-4;
  o.maxIterations = 2000;
  auto g = testutil::solveText(json, o);
  ASSERT_TRUE(g.stats.converged);
  for (double fraction : {1.0, hr::SolverOptions{}.shootFraction}) {
    o.shootFraction = fraction;
    auto s = testutil::solveText(json, shooting(o));
    ASSERT_TRUE(s.stats.converged) << "fraction " << fraction;
    // Room A's objects (the box B stays dark, a ratio of two leaks: its light is bounded below).
    double worst = 0.0;
    for (std::uint32_t obj = 0; obj < 4; ++obj)
      worst = std::max(worst, std::abs(s.meanRadiosity(obj).y / g.meanRadiosity(obj).y - 1.0));
    std::printf("  box B: shoot %.3g gather %.3g W/m^2, room A walls %.3g\n", s.meanRadiosity(4).y, g.meanRadiosity(4).y,
                g.meanRadiosity(0).y);
    std::printf("second enclosure, eps 1e-3, shoot fraction %.2f: imbalance shoot %.3g gather %.3g, worst object %.3g\n",
                fraction, imbalance(s), imbalance(g), worst);
    EXPECT_LT(std::abs(imbalance(s)), 0.01) << "fraction " << fraction;
    EXPECT_LT(worst, 0.03) << "fraction " << fraction;
  }
  EXPECT_LT(std::abs(imbalance(g)), 0.02);
}

}  // namespace

namespace {

// Two closed rooms 10 m apart, each with a lamp and a sphere of 128 patches. A sphere patch shoots
// less than the threshold (eps x emitted), so the oracle kept its single link to the root cluster
// (refine.cpp: such a link can carry no more than its sender sends), whose centre lies between the
// rooms: the far-field model across overlapping nodes gave the room 1/25 of that light or none, and
// the spheres lost 26 % of what they shot. Shooting was 1.59 % out and its objects 1.2-2.1 % under
// gathering's (gathering, whose senders are clusters, -0.22 %). Such a link now carries the power
// its sender's rays find in the cluster (transfer.cpp, measureOverlap): -0.09 %, objects within
// 0.7 %. Bars: balance 1 %; walls and spheres within 1 % of gathering, the two schemes' own
// discretisation difference at this threshold (the Cornell box test above: 0.9 % at 2e-4). The
// lamps only emit (no reflectance): equal in both schemes, not compared.
TEST(Shooting, DimShootersInTwoRoomsLoseNoLight) {
  const std::string json = twoRoomsWithSpheres();
  hr::SolverOptions o = testutil::options(2e-4, 6);
  auto g = testutil::solveText(json, o);
  auto s = testutil::solveText(json, shooting(o));
  ASSERT_TRUE(g.stats.converged);
  ASSERT_TRUE(s.stats.converged);
  std::printf("two rooms with spheres, eps 2e-4: imbalance shoot %.3g gather %.3g\n", imbalance(s), imbalance(g));
  EXPECT_LT(std::abs(imbalance(s)), 0.01);
  EXPECT_LT(std::abs(imbalance(g)), 0.01);
  for (std::uint32_t obj : {0u, 2u, 3u, 5u}) {  // walls and sphere of each room
    const double d = s.meanRadiosity(obj).y / g.meanRadiosity(obj).y - 1.0;
    std::printf("  object %u: shoot/gather - 1 = %.3g\n", obj, d);
    EXPECT_LT(std::abs(d), 0.01) << "object " << obj;
  }
}

}  // namespace
