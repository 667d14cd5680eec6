// The VISION-like host's iteration: emitters start with their light unshot; each iteration shoots
// all unshot light (shoot.cpp) and pushes what arrived down to the leaves, where it becomes the next
// iteration's unshot light (push_pull.cpp); the run ends when the unshot power is below tolerance of
// the emitted power, and the energy audit (audit.cpp) closes it.
#include <tbb/task_arena.h>
#include <time.h>
#include <vision/solver.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "state.h"

namespace vision {

namespace {

double cpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// Wall and CPU time of a phase.
struct Clock {
  hr::PhaseStat& st;
  std::chrono::steady_clock::time_point w0 = std::chrono::steady_clock::now();
  double c0 = cpuSeconds();
  ~Clock() {
    st.wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    st.cpu += cpuSeconds() - c0;
  }
};

}  // namespace

namespace detail {
void sawThread(std::atomic<std::uint64_t>& mask) {
  int i = tbb::this_task_arena::current_thread_index();
  if (i >= 0) mask.fetch_or(std::uint64_t(1) << (i % 64), std::memory_order_relaxed);
}
}  // namespace detail

TreeCounts countElements(const Hierarchy& h) {
  TreeCounts n;
  for (const Element& r : h.roots())
    forEachElement(r, [&](const Element& e) {
      ++n.elements;
      n.leaves += e.leaf() ? 1 : 0;
    });
  return n;
}

struct Solver::Impl {
  detail::State s;
  hr::Progress* progress;
  hr::Progress silent{true};
  double unshot = 0.0, visShare = 0.0;
  Impl(const hr::Scene& sc, Hierarchy& h, const CurvedVisibility& v, const hr::SolverOptions& o, hr::Progress* p)
      : s(sc, h, v, o), progress(p ? p : &silent) {}

  void initialLight(hr::SolveStats& st) {
    for (Element& r : s.h.roots()) {
      const hr::Material& m = s.material(r);
      r.B = r.U = hr::kPi * m.emission;
      r.P = r.g.area * r.U;
      st.emittedW += r.P;
    }
    s.emitted = hr::luminance(st.emittedW);
    s.threshold = s.opt.eps * s.emitted;
    // A pair's visibility may move at most this much power (one standard error), as on the other host.
    s.visTolerance = std::min(s.opt.eps, 2e-4) * s.emitted;
    s.minArea = s.opt.minArea > 0.0 ? s.opt.minArea : s.h.totalArea() * 1e-6;
    detail::indexClusters(s);
  }

  hr::SolveStats solve() {
    hr::SolveStats st;
    const auto t0 = std::chrono::steady_clock::now();
    st.initialPatches = s.h.surfaces().size();
    initialLight(st);
    {
      Clock c(st.pushPull);
      unshot = detail::pushPull(s, false);  // no light received yet: powers and tables from the emitters
    }
    for (int it = 1; it <= s.opt.maxIterations; ++it) {
      const auto ti = std::chrono::steady_clock::now();
      progress->phase("iteration " + std::to_string(it) + ": shoot");
      const std::size_t before = countElements(s.h).elements;
      std::uint64_t used;
      {
        Clock c(st.refine);
        used = detail::shoot(s);
      }
      st.linksComputed += used;
      progress->phase("iteration " + std::to_string(it) + ": push/pull");
      {
        Clock c(st.pushPull);
        unshot = detail::pushPull(s);
      }
      if (!std::isfinite(unshot)) throw std::runtime_error("non-finite radiosity after iteration " + std::to_string(it));
      TreeCounts n = countElements(s.h);
      hr::IterationStat is;
      is.iteration = it;
      is.residualW = unshot;
      is.unconvergedW = unshot;
      is.links = 0;
      is.elements = n.elements;
      is.refined = n.elements - before;
      is.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - ti).count();
      st.history.push_back(is);
      st.iterations = it;
      char buf[256];
      std::snprintf(buf, sizeof buf, "iteration %d: unshot %.3e W (%.2e of emitted), interactions %llu (none kept), elements %zu",
                    it, unshot, unshot / std::max(s.emitted, 1e-300), static_cast<unsigned long long>(used), n.elements);
      progress->note(buf);
      if (unshot <= s.opt.tolerance * s.emitted) {
        st.converged = true;
        break;
      }
    }
    if (!st.converged)
      progress->note("NOT CONVERGED after " + std::to_string(s.opt.maxIterations) + " iterations (raise --max-iterations)");
    progress->phase("energy balance");
    detail::Audit a;
    {
      Clock c(st.energy);
      a = detail::auditEnergy(s);
    }
    st.absorbedW = a.absorbed, st.escapedW = a.escaped, st.backAbsorbedW = a.back, st.auditStdErrW = a.stdErr;
    // The same honest-reporting rule as the BRIGHT-like host: beyond --max-imbalance plus the
    // audit's own noise the answer is not trustworthy (exit 3).
    judgeEnergy(st, s.opt.maxImbalance);
    // Shadow rays are traced inside the shooting tasks: their share of the shooting threads' time.
    const double threadNs = 1e9 * st.refine.cpu;
    visShare = threadNs > 0.0 ? std::min(1.0, double(s.visibilityNs.load()) / threadNs) : 0.0;
    st.visibility.wall = st.refine.wall * visShare;
    st.visibility.cpu = 1e-9 * double(s.visibilityNs.load());
    st.refine.threads = st.visibility.threads = std::popcount(s.shootThreads.load());
    st.pushPull.threads = std::popcount(s.pushThreads.load());
    st.energy.threads = std::popcount(s.auditThreads.load());
    st.tRefine = st.refine.wall, st.tVisibility = st.visibility.wall, st.tPushPull = st.pushPull.wall, st.tEnergy = st.energy.wall;
    TreeCounts n = countElements(s.h);
    st.elements = n.elements, st.leaves = n.leaves, st.clusters = s.h.clusters().size();
    st.links = 0;
    st.linkBytes = 0;
    st.elementBytes = n.elements * sizeof(Element);
    st.rays = s.rays.load();
    st.tTotal = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return st;
  }
};

Solver::Solver(const hr::Scene& scene, Hierarchy& h, const CurvedVisibility& vis, const hr::SolverOptions& opt,
               hr::Progress* progress)
    : impl_(std::make_unique<Impl>(scene, h, vis, opt, progress)) {}
Solver::~Solver() = default;
hr::SolveStats Solver::solve() { return impl_->solve(); }
double Solver::unshotW() const { return impl_->unshot; }
double Solver::visibilityShare() const { return impl_->visShare; }

}  // namespace vision
