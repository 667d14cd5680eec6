// Convergence of the linear system a fixed set of links defines: sweeps (gather + push/pull) whose
// fixed point is the radiosity solution, accelerated by Anderson mixing of the leaves' irradiance.
// Plain gathering (Jacobi) shrinks the error by about the albedo per sweep: 917 sweeps for a closed
// box at rho 0.99, some 7000 at 0.999. See docs/solver.md "Convergence" for the choice and figures.
//
// Refinement is paced by the light: links are refined for the light their senders send, so within
// one refinement pass no node's power (element, or cluster: A B summed, W) may grow beyond
// kGrowthPerPass times what it had when the pass refined, plus a slack of the power threshold.
// Without it, links refined while their senders were dark carried converged light: on the Soda
// Shoppe the second sweep over pass-1 links moved 3.6 times the power reflected in the first, and
// a white room at rho 0.99 carried a hundred times the light its links were refined for, whose
// misplacement then split 3.1 M links where paced passes need 0.9 M. The pass that declares
// convergence refines with the converged light and splits nothing, so pacing never loosens the
// oracle; it only keeps intermediate states honest.
#pragma once
#include <vector>

#include "solver_state.h"

namespace hr::detail {

class Accelerator {
 public:
  /// depth: how many past sweeps the mixing uses (0: plain sweeps). Acceleration is switched off
  /// when an extension is attached: its light lives in its own state, which the mixing of the
  /// host's irradiance cannot move consistently, so such runs keep one sweep per refinement.
  Accelerator(SolverState& s, int depth);

  bool enabled() const { return depth_ > 0; }

  /// Forgets the history: the links or the leaves changed (after every refinement pass).
  void restart();

  /// One sweep over the current links: gather, then push/pull. Returns the fixed-point residual,
  /// the power the sweep changed, sum over leaves of A |B_new - B_old| (luminance of the
  /// per-channel magnitudes), W.
  double sweep();
  /// After a sweep, when another will follow and acceleration is on: moves the leaves' irradiance
  /// on to the extrapolated next iterate, the rest of the hierarchy (inner radiosity, cluster
  /// tables) made consistent with it. Returns false when the pass should end instead (refine
  /// first): some node's power reached its cap (the iterate is then taken only that far, checked
  /// by one more sweep), or acceleration is off.
  bool extrapolate();

  static constexpr double kGrowthPerPass = 2.0;
  static constexpr double kPowerSlack = 1e-3;  // of the emitted power, or eps if finer (refine.cpp)

 private:
  void collectLeaves();
  /// Power leaving every node (elements, then clusters) when the leaves receive irradiance x, W
  /// (luminance).
  void nodePower(const std::vector<Rgb>& x, std::vector<double>& P) const;
  /// The largest t in [0, 1] for which g + t (x - g) keeps every node within its cap, from the
  /// nodes' powers at g and x (0 when g itself is beyond).
  double allowedStep(const std::vector<double>& Pg, const std::vector<double>& Px) const;
  /// Anderson (type II) step per channel from x (irradiance before the sweep) and g (after);
  /// returns the next iterate in x.
  void mix(std::vector<Rgb>& x, const std::vector<Rgb>& g);
  /// Gives every leaf the irradiance x (W/m^2) and makes the hierarchy consistent with it.
  void setLeafIrradiance(const std::vector<Rgb>& x);

  SolverState& s_;
  int depth_;
  std::vector<std::uint32_t> leaves_;      // leaf element ids, ascending
  std::vector<std::uint32_t> clusterLinks_;  // links whose receiver is a cluster
  std::vector<Rgb> w_;  // per leaf, per channel: A rho^2, the least-squares weight (power residual)
  std::vector<Rgb> x_, g_, fPrev_, gPrev_;
  bool havePrev_ = false;
  std::vector<std::vector<Rgb>> dF_, dG_;  // newest last: differences of residuals and of sweep results
  double prevRes_ = 0.0, last_ = 0.0;  // residual before the last extrapolation, and the latest, W
  bool capped_ = false;                // the last extrapolation was cut at the light cap
  std::vector<double> Pref_;        // nodes' power when the pass refined, W
  double slack_ = 0.0;              // growth any node may have regardless, W
};

}  // namespace hr::detail
