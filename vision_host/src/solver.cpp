// The VISION-like host's iteration: emitters start with their light unshot; each iteration shoots
// all unshot light (shoot.cpp) and pushes what arrived down to the leaves, where it becomes the next
// iteration's unshot light (push_pull.cpp); the run ends when the unshot power is below tolerance of
// the emitted power, and the energy audit (audit.cpp) closes it. With an extension, between a shot and
// its push the new elements are numbered (node_view.cpp) and announced (attach, split) and every
// node's unshot light is cleared (shot), as the whole scene has just shot it; the push then hands
// the extension this shot's samples (push_pull.cpp).
#include <tbb/parallel_for.h>
#include <vision/solver.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "state.h"

namespace vision {

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
  detail::NodeView view;
  hr::Progress* progress;
  hr::Progress silent{true};
  double unshot = 0.0, visShare = 0.0;
  Impl(const hr::Scene& sc, Hierarchy& h, const CurvedVisibility& v, const hr::SolverOptions& o, hr::Extension* e,
       hr::Progress* p)
      : s(sc, h, v, o), view(sc, h), progress(p ? p : &silent) {
    if (e && !e->canShoot())
      throw hr::InputError("--algorithm " + std::string(e->name()) +
                           ": gathers only, and the VISION-like host shoots (use --host bright --iteration gather)");
    s.ext = e;
    s.view = &view;
    markOwned();
  }

  /// Surfaces whose material the extension simulates, and the clusters holding any.
  void markOwned() {
    s.ownedSurface.assign(s.h.surfaces().size(), 0);
    s.ownedCluster.assign(s.h.clusters().size(), 0);
    if (!s.ext) return;
    for (std::size_t i = 0; i < s.h.surfaces().size(); ++i)
      s.ownedSurface[i] = s.ext->simulates(view.material(s.h.surfaces()[i].material)) ? 1 : 0;
    // Clusters are built parents first: a reverse sweep sees children first.
    for (std::size_t c = s.h.clusters().size(); c-- > 0;) {
      const Cluster& cl = s.h.clusters()[c];
      for (std::uint32_t k : cl.clusters) s.ownedCluster[c] |= s.ownedCluster[k];
      for (std::uint32_t k : cl.surfaces) s.ownedCluster[c] |= s.ownedSurface[k];
    }
    markReflectors();
  }

  /// As the BRIGHT-like host's oracle: a sharp reflector's image of a sender is blurred and misplaced
  /// when it sees a sender wider than its lobe, so such interactions are refined (hr::Reflector).
  void markReflectors() {
    std::vector<hr::Reflector> r(s.h.surfaces().size());
    bool any = false;
    for (std::size_t i = 0; i < r.size(); ++i) {
      if (!s.ownedSurface[i]) continue;
      r[i] = hr::usableReflector(s.ext->reflector(view.material(s.h.surfaces()[i].material)));
      any = any || r[i].albedo > 0.0;
    }
    if (!any) return;
    s.surfaceReflector = std::move(r);
    s.clusterReflector.assign(s.h.clusters().size(), hr::Reflector{0.0, hr::kPi});
    for (std::size_t c = s.h.clusters().size(); c-- > 0;) {
      const Cluster& cl = s.h.clusters()[c];
      for (std::uint32_t k : cl.clusters) hr::keepSharpest(s.clusterReflector[c], s.clusterReflector[k]);
      for (std::uint32_t k : cl.surfaces) hr::keepSharpest(s.clusterReflector[c], s.surfaceReflector[k]);
    }
  }

  /// After a shot: number its new elements; the extension learns of them and clears the unshot light
  /// every node has just sent.
  void afterShot() {
    std::vector<Element*> split;
    view.number(split);
    if (!s.ext) return;
    s.ext->attach(view);
    for (Element* e : split)
      if (s.owned(*e)) s.ext->split(hr::NodeId{e->id}, view.children(hr::NodeId{e->id}));
    auto& roots = s.h.roots();
    tbb::parallel_for(std::size_t(0), roots.size(), [&](std::size_t i) {
      if (s.owned(roots[i])) s.ext->shot(hr::NodeId{roots[i].id});
    });
  }

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
    if (s.ext) s.ext->attach(view);
    {
      hr::PhaseTimer c(st.pushPull);
      unshot = detail::pushPull(s, false);  // no light received yet: powers and tables from the emitters
    }
    for (int it = 1; it <= s.opt.maxIterations; ++it) {
      const auto ti = std::chrono::steady_clock::now();
      progress->phase("iteration " + std::to_string(it) + ": shoot");
      const std::size_t before = countElements(s.h).elements;
      std::uint64_t used;
      {
        hr::PhaseTimer c(st.refine);
        used = detail::shoot(s);
        afterShot();
      }
      st.linksComputed += used;
      progress->phase("iteration " + std::to_string(it) + ": push/pull");
      {
        hr::PhaseTimer c(st.pushPull);
        unshot = detail::pushPull(s) + detail::extensionUnshot(s);
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
      is.samples = is.samplesAtOnce = s.handed.exchange(0);  // a pass's samples are reflected together
      st.peakSamples = std::max(st.peakSamples, is.samples);
      st.peakSamplesAtOnce = std::max(st.peakSamplesAtOnce, is.samplesAtOnce);
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
    st.unshotW = unshot;
    if (!st.converged)
      progress->note("NOT CONVERGED after " + std::to_string(s.opt.maxIterations) + " iterations (raise --max-iterations)");
    progress->phase("energy balance");
    hr::audit::Totals a;
    {
      hr::PhaseTimer c(st.energy);
      a = detail::auditEnergy(s);
    }
    // The same honest-reporting rule as the BRIGHT-like host: beyond --max-imbalance plus the
    // audit's own noise the answer is not trustworthy (exit 3).
    hr::audit::record(st, a, s.opt.maxImbalance);
    // Shadow rays are traced inside the shooting tasks: their share of the shooting threads' time.
    const double threadNs = 1e9 * st.refine.cpu;
    visShare = threadNs > 0.0 ? std::min(1.0, double(s.visibilityNs.load()) / threadNs) : 0.0;
    st.visibility.wall = st.refine.wall * visShare;
    st.visibility.cpu = 1e-9 * double(s.visibilityNs.load());
    st.refine.threads = st.visibility.threads = hr::threadCount(s.shootThreads);
    st.pushPull.threads = hr::threadCount(s.pushThreads);
    st.energy.threads = hr::threadCount(s.auditThreads);
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
               hr::Extension* ext, hr::Progress* progress)
    : impl_(std::make_unique<Impl>(scene, h, vis, opt, ext, progress)) {}
Solver::~Solver() = default;
hr::SolveStats Solver::solve() { return impl_->solve(); }
double Solver::unshotW() const { return impl_->unshot; }
double Solver::visibilityShare() const { return impl_->visShare; }
const hr::HostView& Solver::view() const { return impl_->view; }

}  // namespace vision
