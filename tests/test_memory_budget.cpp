// The memory budget (--memory-mb): the controller that lowers the threshold pass by pass, tested
// against a synthetic memory law (no machine in the loop), and the command end to end: a larger
// budget never refines less, and the peak resident memory stays near the budget.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

#include "helpers.h"
#include "memory_budget.h"
#include "test_dir.h"

namespace {

constexpr double kMB = 1048576.0;

/// A solve whose memory above a 100 MB base is c * eps^-alpha MB (outputs included), driven by the
/// controller until it freezes or reaches the requested eps. Returns the final eps; peak in MB.
double drive(double budgetMB, double requested, double alpha, double& peakMB) {
  hr::detail::MemoryBudget b(std::size_t(budgetMB * kMB), requested);
  b.start(std::size_t(100 * kMB));
  double eps = b.eps();
  peakMB = 100;
  for (int pass = 0; pass < 100; ++pass) {
    eps = b.eps();
    const bool atRequested = b.atRequested();
    if (!b.frozen()) peakMB = std::max(peakMB, 100.0 + 0.5 * std::pow(eps / 1e-2, -alpha));
    b.afterPass(std::size_t(peakMB * kMB), std::size_t(peakMB * kMB), 0, 0);
    if (b.frozen() || atRequested) break;  // a pass at the requested eps is the last one here
  }
  return eps;
}

TEST(MemoryBudget, TheControllerFillsTheBudgetWithoutOverrunningIt) {
  for (double alpha : {0.6, 0.8, 1.0, 1.5}) {
    double lastEps = 1.0;
    for (double budget : {150.0, 200.0, 300.0, 500.0, 1000.0}) {
      double peak = 0.0;
      const double eps = drive(budget, 1e-9, alpha, peak);
      SCOPED_TRACE("alpha " + std::to_string(alpha) + ", budget " + std::to_string(budget));
      EXPECT_LE(peak, budget * 1.0 + 1e-9);
      EXPECT_GE(peak, budget * 0.9);
      EXPECT_LT(eps, lastEps) << "a larger budget refines further";
      lastEps = eps;
    }
  }
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

double epsReached(const std::string& dir) {
  nlohmann::json j = nlohmann::json::parse(std::ifstream(dir + "/stats.json"));
  return j["memory_budget"]["eps_reached"].get<double>();
}

#if defined(__SANITIZE_ADDRESS__)
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

}  // namespace
