// What every host's solver takes and reports: the options (from a scene's settings and the
// command line), the per-iteration and per-phase statistics, and the honest-reporting rule for the
// energy audit. Both hosts fill the same SolveStats, so stats.json and the exit codes mean the same
// whichever host ran; the hosts themselves are bright/include/hr/solver.h and vision/solver.h.
#pragma once
#include <hr/scene.h>
#include <hr/types.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hr {

/// How light is propagated: Jacobi gathering over every link, or shooting passes from the nodes with
/// the most unshot power (progressive). The VISION-like host always shoots.
enum class Iteration { Gather, Shoot };

struct SolverOptions {
  double eps = 2e-4;          // refine a link while its error estimate exceeds eps * emitted power
  int maxLevel = 6;           // quadtree depth below a root patch
  double minArea = 0.0;       // m^2; 0: total area * 1e-6
  int raysPerLink = 4;
  int maxIterations = 200;
  double tolerance = 1e-4;    // converged when the iteration's power change < tolerance * emitted
  int acceleration = 5;       // Anderson mixing depth over fixed links (0: one plain sweep per pass)
  double maxImbalance = 0.02;  // the energy audit may find at most this fraction of the emitted
                               // power unaccounted for (plus 3 of its standard errors), else energyOk
                               // is false
  /// TEST ONLY: every shadow ray reports the way clear, so occluders do not occlude and the answer
  /// is wrong on purpose; the energy audit must catch it. Set by SolverOptions::from() when the
  /// environment variable GLOSSYHR_TEST_ONLY_UNBLOCKED_SHADOW_RAYS is 1. Never for real runs.
  bool testOnlyUnblockedShadowRays = false;
  /// TEST ONLY: a shooting pass's push/pull visits every subtree, not only those the pass changed:
  /// the answer the pruned push must equal bit for bit.
  bool testOnlyPushEverything = false;
  /// TEST ONLY: every refinement round is capped at this many links, as a memory budget caps it
  /// (capRound), with no machine in the loop, so that a capped solve repeats exactly. 0: no cap.
  std::size_t testOnlyMaxLinks = 0;
  std::uint64_t seed = 1;
  Iteration iteration = Iteration::Gather;
  /// Shooting: a patch shoots in a pass when its unshot power is at least this fraction of the
  /// largest patch's (1: one patch per pass, fewest samples held at once; smaller: fewer passes).
  double shootFraction = 0.1;
  /// Gathering: a peak resident memory budget (bytes; 0 none). Refinement starts at a coarse
  /// threshold and comes down toward eps pass by pass as far as the budget allows (memory_budget.h).
  std::size_t memoryBudgetBytes = 0;
  static SolverOptions from(const Settings& s);
};

struct IterationStat {
  int iteration = 0;           // sweep (gather + push/pull), counted over the whole solve
  int pass = 0;                // refinement pass the sweep belongs to
  double residualW = 0.0;      // sum over leaves of area * |B_new - B_old| (luminance), W
  double unconvergedW = 0.0;   // residual extrapolated by the geometric series of mean reflectance
  std::size_t links = 0, elements = 0, refined = 0;
  std::size_t shooters = 0;    // shooting: patches that shot in this pass
  std::size_t pushedPatches = 0;  // shooting: root patches the pass's push/pull visited (the rest kept)
  std::size_t samples = 0;     // Illumination Samples handed to the extension's gather hook
  // The most of them one push carried to the leaves and held for reflection at once: all of a
  // gathering iteration's; one batch of a shooting pass's (shoot.cpp reflects a pass in batches).
  std::size_t samplesAtOnce = 0;
  std::size_t batches = 0;     // shooting: pushes the pass's samples were reflected in
  double seconds = 0.0;
};

/// One phase's cost: wall and CPU seconds (CPU of the whole process while the phase ran) and the
/// number of distinct worker threads that did some of its work.
struct PhaseStat {
  double wall = 0.0, cpu = 0.0;
  int threads = 0;
};

struct SolveStats {
  double tTotal = 0, tRefine = 0, tVisibility = 0, tGather = 0, tPushPull = 0, tEnergy = 0;
  PhaseStat visibility, refine, gather, pushPull, energy;
  std::size_t initialPatches = 0, elements = 0, leaves = 0, clusters = 0, links = 0;  // links: stored at the end
  std::uint64_t linksComputed = 0;  // interactions whose transfer was evaluated, over the whole run
  std::uint64_t rays = 0;
  std::size_t linkBytes = 0, elementBytes = 0;
  Rgb emittedW{0.0}, absorbedW{0.0}, escapedW{0.0};  // W per channel
  Rgb backAbsorbedW{0.0};  // the part of absorbedW that reached the black back of a one-sided surface
  Rgb auditStdErrW{0.0};   // standard error of the audit's ray estimate (escaped and back faces), W
  /// What the audit's imbalance (emitted - absorbed - escaped) may be per channel, W: the options'
  /// maxImbalance of the emitted power plus 3 standard errors of the audit's own estimate.
  Rgb allowedImbalanceW{0.0};
  bool energyOk = true;    // every channel's |imbalance| within allowedImbalanceW
  int iterations = 0;      // gathering sweeps or shooting passes
  bool converged = false;
  bool diverged = false;  // stopped: the residual kept growing beyond the emitted power (solver.cpp)
  Iteration iteration = Iteration::Gather;
  double unshotW = 0.0;         // shooting: unshot power left at the end (luminance), W
  double shootFraction = 0.0;   // shooting: SolverOptions::shootFraction
  std::size_t peakSamples = 0;  // the most Illumination Samples handed over in one iteration or pass
  std::size_t peakSamplesAtOnce = 0;  // the most held for reflection at once (IterationStat::samplesAtOnce)
  std::size_t memoryBudgetBytes = 0;  // SolverOptions::memoryBudgetBytes
  double epsReached = 0.0;            // the finest threshold refinement used (eps without a budget)
  bool memoryBudgetExceeded = false;  // the coarsest pass alone did not fit in the budget
  std::vector<IterationStat> history;
};

/// Honest reporting, the same for every host: the audit's imbalance beyond maxImbalance of the
/// emitted power plus 3 of the audit's standard errors, in any channel, clears energyOk.
void judgeEnergy(SolveStats& st, double maxImbalance);

}  // namespace hr
