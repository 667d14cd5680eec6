// Diffuse hierarchical radiosity with clustering (in the manner of Smits et al. 1994 and Sillion
// 1995). One iteration = refine links (refine.cpp) -> gather along links -> push/pull
// (push_pull.cpp); the energy audit (energy_audit.cpp) closes the run. This file holds the gathering
// loop and convergence; shooting passes are in shoot.cpp, the host's view for an extension in
// tree_view.cpp.
#include <hr/solver.h>
#include <hr/output.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <malloc.h>
#include <string>

#include "convergence.h"
#include "memory_budget.h"
#include "solver_state.h"
#include "tree_view.h"

namespace hr {

/// Consecutive growing residuals above the emitted power after which a solve is declared diverging.
constexpr int kDivergingIterations = 3;
/// A pass whose refinement split at most this fraction of the links, and whose sweeps then reached
/// the tolerance, ends the solve: the light is settled to the tolerance on the links it has, and the
/// oracle is met by all but a few links whose estimates crossed the threshold only as the light
/// settled in its last digits (Jacobi light grows toward the answer, so links near the threshold
/// cross it one by one: the simple Soda Shoppe split 51, 33, 15, 7, 7, 2, 1 of 1.56 M links in its
/// last seven passes, each a full glossy sweep, 30 % of the solve; stopping at the first such pass
/// took it from 161 to 122 s, its image within 2.1e-5 relative RMSE of the fully settled one).
constexpr double kSettledSplitFraction = 1e-4;

using detail::Link;
using detail::SolverState;

struct Solver::Impl {
  SolverState s;
  detail::TreeView view;  // what an extension sees of the hierarchy (tree_view.h)
  Progress* progress;
  Progress silent{true};

  Impl(const Scene& sc, Hierarchy& hi, const Visibility& v, const SolverOptions& o, Extension* e, Progress* p)
      : s(sc, hi, v, o, e), view(sc, hi, s.open), progress(p ? p : &silent) {}

  /// Clusters made only of emitters (a lamp of many patches): their links carry direct light as an
  /// emitting element's do, and take as many shadow rays (transfer.cpp).
  void markEmitters() {
    s.clusterEmits.assign(s.h.clusters().size(), 1);
    for (std::size_t c = s.h.clusters().size(); c-- > 0;)
      for (NodeId k : s.h.cluster(static_cast<std::uint32_t>(c)).children)
        s.clusterEmits[c] &= static_cast<std::uint8_t>(s.emits(k));  // children's entries are set
  }

  void markOwned() {
    s.clusterOwned.assign(s.h.clusters().size(), 0);
    if (!s.ext) return;
    for (std::uint32_t p = 0; p < s.h.patches().size(); ++p)
      s.owned[p] = s.ext->simulates(view.material(s.h.patches()[p].material)) ? 1 : 0;
    // Clusters are built with children after parents: a reverse sweep sees children first.
    for (std::size_t c = s.h.clusters().size(); c-- > 0;)
      for (NodeId k : s.h.cluster(static_cast<std::uint32_t>(c)).children)
        s.clusterOwned[c] |= k.isCluster() ? s.clusterOwned[k.index()] : s.owned[k.index()];
    markReflectors();
  }

  /// Each simulated material's Reflector and each cluster's sharpest one (largest albedo, narrowest
  /// lobe, not necessarily of one material: a bound for the oracle). Left empty when no material
  /// has one, so the oracle's reflection term costs nothing then.
  void markReflectors() {
    std::vector<Reflector> m(s.scene.materials.size());
    bool any = false;
    for (std::uint32_t i = 0; i < m.size(); ++i) {
      const MaterialInfo info = view.material(i);
      if (!s.ext->simulates(info)) continue;
      m[i] = usableReflector(s.ext->reflector(info));
      any = any || m[i].albedo > 0.0;
    }
    if (!any) return;
    s.materialReflector = std::move(m);
    s.clusterReflector.assign(s.h.clusters().size(), Reflector{0.0, kPi});
    for (std::size_t c = s.h.clusters().size(); c-- > 0;)
      for (NodeId k : s.h.cluster(static_cast<std::uint32_t>(c)).children)
        keepSharpest(s.clusterReflector[c], k.isCluster() ? s.clusterReflector[k.index()] : s.reflector(k));
  }

  static PhaseStat stat(const detail::PhaseClock& c) { return {c.wall, c.cpu, c.threads()}; }

  /// One sweep's line in the progress log, and the progress bar.
  void report(const SolveStats& st, const IterationStat& is) {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "iteration %d (pass %d): residual %.3e W (%.2e of emitted), unconverged ~%.3e W, links %zu, elements %zu, split %zu",
                  is.iteration, is.pass, is.residualW, is.residualW / std::max(s.emittedPower, 1e-300), is.unconvergedW,
                  is.links, is.elements, is.refined);
    progress->note(buf);
    // Convergence as a percentage: how far the residual has fallen, on a log scale, from the
    // first iteration's toward the tolerance.
    double first = st.history.front().residualW, target = s.opt.tolerance * s.emittedPower;
    if (first > target && is.residualW > 0.0)
      progress->update(std::clamp(std::log(first / is.residualW) / std::log(first / target), 0.0, 1.0));
  }

  SolveStats solve() {
    SolveStats st;
    auto t0 = std::chrono::steady_clock::now();
    const Hierarchy& h = s.h;
    st.initialPatches = h.patches().size();
    double totalArea = 0.0;
    for (const Patch& p : h.patches()) totalArea += p.area;
    s.minArea = s.opt.minArea > 0.0 ? s.opt.minArea : totalArea * 1e-6;
    s.sceneArea = totalArea;
    if (s.opt.testOnlyUnblockedShadowRays)
      progress->note("TEST ONLY: shadow rays are never blocked (GLOSSYHR_TEST_ONLY_UNBLOCKED_SHADOW_RAYS=1): the answer is wrong on purpose");
    s.growArrays();
    markOwned();
    markEmitters();
    for (const Patch& p : h.patches()) st.emittedW += kPi * s.scene.materials[p.material].emission * p.area;
    s.emittedPower = luminance(st.emittedW);
    detail::checkCanAbsorb(s);
    s.allocateTables();
    detail::pushPull(s);  // no links yet: cluster intensities from the emitters
    s.links.clear();
    s.links.push_back(Link{h.root(), h.root()});
    double rhoMean = 0.0;
    for (const Patch& p : h.patches()) rhoMean += luminance(s.scene.materials[p.material].diffuse) * p.area;
    rhoMean /= std::max(totalArea, 1e-300);
    // Each pass refines the links, then sweeps over them (gather + push/pull) until the residual
    // is below the tolerance: with acceleration (convergence.cpp) refinement, the costly part, runs
    // a few times instead of once per sweep. Converged when a pass splits (almost) nothing
    // (kSettledSplitFraction) and its sweeps reach the tolerance. With an extension attached every
    // pass sweeps once (plain Jacobi).
    // Shooting passes are in shoot.cpp.
    detail::Accelerator acc(s, s.opt.acceleration);
    const double target = s.opt.tolerance * s.emittedPower;
    int it = 0;
    int grew = 0;  // consecutive iterations whose residual grew
    if (s.opt.iteration == Iteration::Shoot) detail::shootPasses(s, view, *progress, st);
    detail::MemoryBudget budget(s.opt.memoryBudgetBytes, s.opt.eps);
    // glibc raises its mmap threshold each time a large block is freed (up to 32 MB), so link arrays
    // soon come from the heap, and an array freed there stays resident: a pass that copied its links
    // twice kept both copies (the Cornell box at 60 MB: 12 MB for 15k more links). A fixed threshold
    // gives freed link arrays back, so the resident memory the budget steers by is what is live.
    if (budget.active()) mallopt(M_MMAP_THRESHOLD, 1 << 20);
    if (budget.active() && s.ext) s.ext->memoryBudget(s.opt.memoryBudgetBytes);
    budget.start(peakRssBytes());
    for (int pass = 1; s.opt.iteration == Iteration::Gather && it < s.opt.maxIterations; ++pass) {
      progress->phase("pass " + std::to_string(pass) + ": refine");
      s.opt.eps = budget.eps();
      s.cap = budget.cap();
      s.shadows = !budget.active() || budget.atRequested();
      if (s.opt.testOnlyMaxLinks > 0) s.cap = detail::RefineCap{1.0, 0.0, double(s.opt.testOnlyMaxLinks)};
      if (budget.active() && s.ext) s.ext->limitDirectionalLevels(budget.directionalLevels());
      std::size_t refined = 0;
      s.capCut = false;
      if (!budget.frozen()) refined = detail::refineLinks(s);
      if (s.ext) s.ext->attach(view);
      acc.restart();
      double res = 0.0;
      do {
        ++it;
        auto ti = std::chrono::steady_clock::now();
        progress->phase("iteration " + std::to_string(it) + ": gather");
        res = acc.sweep();
        IterationStat is;
        is.iteration = it;
        is.pass = pass;
        is.residualW = res;
        is.unconvergedW = res * rhoMean / std::max(1e-6, 1.0 - rhoMean);
        is.links = s.links.size();
        is.elements = h.elements().size();
        is.refined = st.history.empty() || st.history.back().pass != pass ? refined : 0;
        is.samples = is.samplesAtOnce = s.samples.exchange(0);  // one push reflects them all
        st.peakSamples = std::max(st.peakSamples, is.samples);
        st.peakSamplesAtOnce = std::max(st.peakSamplesAtOnce, is.samplesAtOnce);
        is.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - ti).count();
        st.history.push_back(is);
        st.iterations = it;
        report(st, is);
        if (!std::isfinite(res)) throw std::runtime_error(detail::nonFiniteWhere(s, "iteration " + std::to_string(it)));
      } while (res > target && it < s.opt.maxIterations && acc.extrapolate());
      const bool finest = budget.frozen() || budget.atRequested();
      if (budget.active()) {
        const std::size_t peak = peakRssBytes();
        const bool cut = s.capCut;
        budget.afterPass(peak, currentRssBytes(), freeHeapBytes(), h.elements().size(), s.links.size(), cut,
                         s.ext ? s.ext->heldBytes() : 0);
        char buf[200];
        std::snprintf(buf, sizeof buf, "memory budget: pass %d refined at eps %.3g%s, peak %.1f MB of %.1f MB%s", pass,
                      s.opt.eps, cut ? " (cut short: the most urgent splits that fit)" : "", double(peak) / 1048576.0,
                      double(s.opt.memoryBudgetBytes) / 1048576.0, budget.frozen() ? "; refinement stops here" : "");
        progress->note(buf);
      }
      const bool settled = double(refined) <= kSettledSplitFraction * double(s.links.size());
      if (settled && res <= target && finest && !budget.directionsSteppedBack()) {
        st.converged = true;
        break;
      }
      // A safety net, whatever the cause: each iteration's change is the light of one more bounce,
      // at most the emitted power even while refinement reshuffles links, and it shrinks with the
      // albedo. A residual that keeps growing beyond the emitted power means energy is being
      // created (it grew ~10x per iteration on a scene that did): running on only costs time and
      // memory (millions of links) and ends in overflow, so the solve stops and says so.
      grew = st.history.size() >= 2 && res > st.history[st.history.size() - 2].residualW ? grew + 1 : 0;
      if (grew >= kDivergingIterations && res > s.emittedPower) {
        st.diverged = true;
        char why[256];
        std::snprintf(why, sizeof why,
                      "DIVERGING: the residual grew %d iterations in a row to %.3g x the emitted power (energy is "
                      "being created); stopped after iteration %d",
                      grew, res / std::max(s.emittedPower, 1e-300), it);
        progress->note(why);
        break;
      }
    }
    st.memoryBudgetBytes = s.opt.memoryBudgetBytes;
    st.epsReached = s.opt.eps;
    st.memoryBudgetExceeded = budget.exceeded();
    if (budget.exceeded())
      progress->note("MEMORY BUDGET EXCEEDED: the coarsest pass alone needs more than the budget allows");
    if (!st.converged && !st.diverged && s.opt.iteration == Iteration::Gather)
      progress->note("NOT CONVERGED after " + std::to_string(s.opt.maxIterations) + " iterations (raise --max-iterations)");
    progress->phase("energy balance");
    // Honest reporting: the audit measures where the power went independently of the links; an
    // imbalance beyond what the options allow plus the audit's own noise makes the answer untrustworthy.
    audit::record(st, detail::auditEnergy(s), s.opt.maxImbalance);
    st.visibility = stat(s.clkVisibility);
    st.refine = stat(s.clkRefine);
    st.gather = stat(s.clkGather);
    st.pushPull = stat(s.clkPushPull);
    st.energy = stat(s.clkEnergy);
    st.tVisibility = st.visibility.wall;
    st.tRefine = st.refine.wall;
    st.tGather = st.gather.wall;
    st.tPushPull = st.pushPull.wall;
    st.tEnergy = st.energy.wall;
    st.elements = h.elements().size();
    st.leaves = static_cast<std::size_t>(
        std::count_if(h.elements().begin(), h.elements().end(), [](const Element& e) { return e.leaf(); }));
    st.clusters = h.clusters().size();
    st.links = s.links.size();
    st.rays = s.rays.load();
    st.linksComputed = s.evaluated.load();
    st.linkBytes = s.links.capacity() * sizeof(Link);
    st.elementBytes = h.elements().capacity() * sizeof(Element) + s.B.capacity() * sizeof(Rgb) * 4;
    st.tTotal = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return st;
  }
};

Solver::Solver(const Scene& scene, Hierarchy& h, const Visibility& vis, const SolverOptions& opt, Extension* ext,
               Progress* progress)
    : impl_(std::make_unique<Impl>(scene, h, vis, opt, ext, progress)) {}
Solver::~Solver() = default;
SolveStats Solver::solve() { return impl_->solve(); }
const std::vector<Rgb>& Solver::radiosity() const { return impl_->s.B; }
const std::vector<Rgb>& Solver::irradiance() const { return impl_->s.Et; }
const std::vector<float>& Solver::openFraction() const { return impl_->s.open; }
const HostView& Solver::view() const { return impl_->view; }

}  // namespace hr
