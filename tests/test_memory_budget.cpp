// The memory budget (--memory-mb): the controller that lowers the threshold pass by pass and the cap
// that cuts a pass short, tested against a synthetic memory law (no machine in the loop), and the
// command end to end: a larger budget never refines less, the peak resident memory stays near the
// budget, and a glossy solve's directional detail follows the budget.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <vector>
#include <fstream>

#include "helpers.h"
#include "memory_budget.h"
#include "test_dir.h"

namespace {

constexpr double kMB = 1048576.0;

/// A synthetic solve: the memory above a 100 MB base is 0.5 (eps/1e-2)^-alpha MB (outputs included),
/// times `jump` below eps `jumpAt` (a step in link count like the Cornell box's between eps 6e-5 and
/// 4e-5, which the fitted law cannot foresee), at bytesPerLink that grows by `drift` per halving of
/// eps (the measured cost per link creeps up as arrays grow). Refinement stops where the cap says,
/// at link granularity, as refine.cpp does.
struct Law {
  double alpha, jumpAt = 0.0, jump = 1.0, drift = 0.0;
};

/// Drives the controller until it freezes or reaches the requested eps. Returns the final eps; the
/// peak in MB.
double drive(double budgetMB, double requested, const Law& law, double& peakMB) {
  hr::detail::MemoryBudget b(std::size_t(budgetMB * kMB), requested);
  b.start(std::size_t(100 * kMB));
  double eps = b.eps(), links = 0.0;
  peakMB = 100;
  for (int pass = 0; pass < 100; ++pass) {
    eps = b.eps();
    const bool atRequested = b.atRequested();
    bool cut = false;
    if (!b.frozen()) {
      double mem = 0.5 * std::pow(eps / 1e-2, -law.alpha) * (eps < law.jumpAt ? law.jump : 1.0);
      const double perLink = 300.0 * (1.0 + law.drift * std::log2(1e-2 / eps));
      links = std::floor(mem * kMB / perLink);
      const hr::detail::RefineCap& cap = b.cap();
      if (!cap.fits(std::size_t(links), 0)) {
        links = std::floor(cap.room / cap.perLink), cut = true;
        mem = links * perLink / kMB;
      }
      peakMB = std::max(peakMB, 100.0 + mem);
    }
    b.afterPass(std::size_t(peakMB * kMB), std::size_t(peakMB * kMB), 0, 0, std::size_t(links), cut);
    if (b.frozen() || atRequested) break;  // a pass at the requested eps is the last one here
  }
  return eps;
}

double drive(double budgetMB, double requested, double alpha, double& peakMB) {
  return drive(budgetMB, requested, Law{alpha}, peakMB);
}

TEST(MemoryBudget, TheControllerFillsTheBudgetWithoutOverrunningIt) {
  for (double alpha : {0.6, 0.8, 1.0, 1.5}) {
    double lastEps = 1.0;
    for (double budget : {150.0, 200.0, 300.0, 500.0, 1000.0}) {
      double peak = 0.0;
      const double eps = drive(budget, 1e-9, alpha, peak);
      SCOPED_TRACE("alpha " + std::to_string(alpha) + ", budget " + std::to_string(budget));
      EXPECT_LE(peak, budget + 0.01);  // the cap stops at a link: within a few bytes
      EXPECT_GE(peak, budget * 0.9);
      EXPECT_LT(eps, lastEps) << "a larger budget refines further";
      lastEps = eps;
    }
  }
}

// The Cornell box's overshoot (peak 1.11-1.17 x a 100 MB budget): a law fitted to the passes before a
// step in link count under-predicts the pass that meets it. The cap, measured per link, cuts that pass
// short instead. Tolerance: the acceptance's 10 % over, and at least 85 % of the budget spent.
TEST(MemoryBudget, AStepInLinkCountIsCutShortNotOverrun) {
  for (double alpha : {0.8, 1.0, 1.3})
    for (double jumpAt : {3e-3, 1e-3, 4e-4, 1.5e-4, 6e-5})
      for (double budget : {150.0, 200.0, 300.0, 500.0, 1000.0}) {
        double peak = 0.0;
        drive(budget, 1e-9, Law{alpha, jumpAt, 1.5, 0.03}, peak);
        SCOPED_TRACE("alpha " + std::to_string(alpha) + ", step at eps " + std::to_string(jumpAt) + ", budget " +
                     std::to_string(budget));
        EXPECT_LE(peak, budget * 1.10);
        EXPECT_GE(peak, budget * 0.85);
      }
}

/// A synthetic glossy solve: the links' memory as in drive(), plus an extension whose distributions
/// take e0 (eps/1e-2)^-alpha MB at the coarsest directional level and `growth` times more per level,
/// rebuilt every pass at the levels the budget allows (so a level raise costs at once, uncapped).
/// Returns the final eps; the peak in MB and the levels of the last pass.
double driveGlossy(double budgetMB, double alpha, double e0, double growth, double& peakMB, int& levels) {
  hr::detail::MemoryBudget b(std::size_t(budgetMB * kMB), 1e-9);
  b.start(std::size_t(100 * kMB));
  double eps = b.eps(), links = 0.0, linkMB = 0.0;
  peakMB = 100;
  for (int pass = 0; pass < 200; ++pass) {
    eps = b.eps();
    levels = b.directionalLevels();
    const double extMB = e0 * std::pow(eps / 1e-2, -alpha) * std::pow(growth, levels - 1);
    bool cut = false;
    if (!b.frozen()) {
      const double perLink = 300.0;
      const double wanted = std::floor(0.5 * std::pow(eps / 1e-2, -alpha) * kMB / perLink);
      links = std::max(links, wanted);
      const hr::detail::RefineCap& cap = b.cap();
      if (!cap.fits(std::size_t(links), 0)) links = std::max(std::floor(cap.room / cap.perLink), 0.0), cut = true;
      linkMB = links * perLink / kMB;
    }
    const double now = 100.0 + linkMB + extMB;
    peakMB = std::max(peakMB, now);
    b.afterPass(std::size_t(peakMB * kMB), std::size_t(now * kMB), 0, 0, std::size_t(links), cut,
                std::size_t(extMB * kMB));
    if (b.frozen() && pass > 3 && b.directionalLevels() == levels) break;
  }
  return eps;
}

TEST(MemoryBudget, ADirectionalLevelComesOnlyWithItsSpatialDetail) {
  // The glossy Cornell box's error rose with the budget when a level was taken and the threshold then
  // stopped coarse (400 MB: level 5 at eps 1.3e-4, 2.8 %; 300 MB: level 4 at 4.1e-5, 1.6 %). Each level
  // taken must have been followed by the threshold two factors of 4 below where it begins (kLevelReach;
  // tolerance: the law's last step, a factor 2), and the peak stays within 10 % of the budget.
  for (double alpha : {0.8, 1.0, 1.3})
    for (double budget : {150.0, 200.0, 300.0, 500.0, 1000.0, 3000.0}) {
      double peak = 0.0;
      int levels = 0;
      const double eps = driveGlossy(budget, alpha, 0.2, 4.0, peak, levels);
      SCOPED_TRACE("alpha " + std::to_string(alpha) + ", budget " + std::to_string(budget));
      EXPECT_LE(peak, budget * 1.10);
      EXPECT_GE(peak, budget * 0.85);
      ASSERT_GE(levels, 1);
      const double begins = 1e-2 / std::pow(4.0, levels - 1);  // where the last level taken begins
      if (levels > 1) {
        EXPECT_LE(eps, 2.0 * begins / 16.0) << "level " << levels;
      }
    }
}

TEST(MemoryBudget, ACappedRoundMakesTheMostUrgentSplitsThatFit) {
  // Room for 1000 + 25 links at 1 byte each; elements cost nothing here but in the third case.
  const hr::detail::RefineCap cap{1.0, 0.0, 1025.0};
  const std::vector<double> urgency = {1.0, 5.0, 3.0, 2.0};
  const std::vector<std::uint32_t> none(4, hr::detail::kNoLeaf);
  EXPECT_EQ(hr::detail::fitMostUrgent(cap, 1000, 10, urgency, std::vector<std::uint32_t>{10, 10, 10, 10}, none, 4),
            (std::vector<std::uint8_t>{0, 1, 1, 0}));
  // A split too large to fit is passed over for a cheaper, less urgent one that does.
  EXPECT_EQ(hr::detail::fitMostUrgent(cap, 1000, 10, urgency, std::vector<std::uint32_t>{5, 10, 30, 10}, none, 4),
            (std::vector<std::uint8_t>{1, 1, 0, 1}));
  // Two splits of one leaf make its four children once.
  const hr::detail::RefineCap byElements{1.0, 1.0, 1000.0 + 10.0 + 4.0 + 3.0};
  EXPECT_EQ(hr::detail::fitMostUrgent(byElements, 1000, 10, urgency, std::vector<std::uint32_t>{1, 1, 1, 1},
                                      std::vector<std::uint32_t>{2, 7, 7, 3}, 4),
            (std::vector<std::uint8_t>{0, 1, 1, 0}));
}

TEST(MemoryBudget, TheRequestedEpsIsAFloorAndATooSmallBudgetIsSaid) {
  double peak = 0.0;
  EXPECT_DOUBLE_EQ(drive(1e6, 1e-3, 1.0, peak), 1e-3) << "a huge budget stops at the requested eps";
  hr::detail::MemoryBudget tiny(std::size_t(50 * kMB), 1e-4);
  tiny.start(std::size_t(100 * kMB));
  EXPECT_TRUE(tiny.frozen());
  EXPECT_TRUE(tiny.exceeded());
  hr::detail::MemoryBudget none(0, 1e-4);
  EXPECT_FALSE(none.active());
  EXPECT_DOUBLE_EQ(none.eps(), 1e-4);
}

nlohmann::json stats(const std::string& dir) { return nlohmann::json::parse(std::ifstream(dir + "/stats.json")); }
double epsReached(const std::string& dir) { return stats(dir)["memory_budget"]["eps_reached"].get<double>(); }

// GHR_SANITIZED: the test drivers are compiled plain in a sanitizer build (tests/CMakeLists.txt),
// but the program they run is not.
#if defined(__SANITIZE_ADDRESS__) || defined(GHR_SANITIZED)
constexpr bool kAsan = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAsan = true;
#else
constexpr bool kAsan = false;
#endif
#else
constexpr bool kAsan = false;
#endif

TEST(MemoryBudget, ALargerBudgetRefinesTheCornellBoxFurther) {
  // AddressSanitizer's shadow memory and quarantine multiply the resident set: budgets in MB mean
  // nothing there.
  if (kAsan) GTEST_SKIP() << "resident memory under AddressSanitizer is not the program's";
  const std::string dir = testutil::testDir().string();
  std::string out;
  ASSERT_EQ(testutil::runCli("solve --quiet --eps 1e-7 --memory-mb 120 -o " + dir + "/a", out), 0) << out;
  ASSERT_EQ(testutil::runCli("solve --quiet --eps 1e-7 --memory-mb 240 -o " + dir + "/b", out), 0) << out;
  EXPECT_LT(epsReached(dir + "/b"), epsReached(dir + "/a"));
}

TEST(MemoryBudget, AGlossySolvesDirectionalDetailFollowsTheBudget) {
  if (kAsan) GTEST_SKIP() << "resident memory under AddressSanitizer is not the program's";
  const std::string dir = testutil::testDir().string();
  const std::string solve = "solve " + std::string(GHR_SOURCE_DIR) +
                            "/scenes/glossy_cornell.json --quiet --algorithm is --dir-eps 0.05 --dir-max-level 5 --eps 1e-7 ";
  std::string out;
  // Exit 0 also says the peak stayed within 10 % of the budget (exit 3 otherwise): without the
  // steering the 60 MB run peaked at 2.1 x (levels raised with the threshold, outputs not counted),
  // and at 1.22 x while the lobe memo kept its default bound (it filled late, after refinement stopped).
  ASSERT_EQ(testutil::runCli(solve + "--memory-mb 60 -o " + dir + "/tight", out), 0) << out;
  // The ample budget well past where level 3 is taken: the budget reads resident memory, which moves
  // from run to run, and at 150 MB level 3 was taken in 5 of 8 runs (2 in the other 3, as the tight
  // run's: a fresh clone's CI failed on it); at 200 and 250 MB in every run (3 and 9 runs), 15-17 s.
  ASSERT_EQ(testutil::runCli(solve + "--memory-mb 250 -o " + dir + "/ample", out), 0) << out;
  const nlohmann::json tight = stats(dir + "/tight"), ample = stats(dir + "/ample");
  const double level = tight["extension"]["dir_max_level_used"].get<double>();
  // At most one level above --dir-min-level 1 at the start (eps 1e-2) and one more per factor 4 below it.
  const double reached = tight["memory_budget"]["eps_reached"].get<double>();
  EXPECT_LE(level, std::min(5.0, 2.0 + std::floor(std::log(1e-2 / reached) / std::log(4.0) + 1e-9)));
  EXPECT_LT(level, ample["extension"]["dir_max_level_used"].get<double>()) << "a tight budget keeps directions coarser";
  EXPECT_LT(tight["extension"]["bytes"].get<double>(), ample["extension"]["bytes"].get<double>());
}

}  // namespace
