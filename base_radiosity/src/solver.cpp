// Diffuse hierarchical radiosity with clustering (in the manner of Smits et al. 1994 and Sillion
// 1995). One iteration = refine links (refine.cpp) -> gather along links -> push/pull
// (push_pull.cpp); the energy audit (energy_audit.cpp) closes the run. This file holds the gathering
// loop, convergence and the host's view for an extension; shooting passes are in shoot.cpp.
#include <hr/solver.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "solver_state.h"

namespace hr {

using detail::Link;
using detail::SolverState;

SolverOptions SolverOptions::from(const Settings& s) {
  SolverOptions o;
  o.eps = s.eps;
  o.maxLevel = s.maxLevel;
  o.minArea = s.minArea;
  o.raysPerLink = s.raysPerLink;
  o.maxIterations = s.maxIterations;
  o.tolerance = s.tolerance;
  o.seed = s.seed;
  return o;
}

struct Solver::Impl final : public HostView {
  SolverState s;
  Progress* progress;
  Progress silent{true};

  Impl(const Scene& sc, Hierarchy& hi, const Visibility& v, const SolverOptions& o, Extension* e, Progress* p)
      : s(sc, hi, v, o, e), progress(p ? p : &silent) {}

  // ---- HostView --------------------------------------------------------------------------
  NodeId root() const override { return s.h.root(); }
  NodeInfo info(NodeId n) const override {
    NodeInfo i;
    if (n.isCluster()) {
      const Cluster& c = s.h.cluster(n.index());
      i.center = c.center;
      i.area = c.area;
      i.bounds = c.bounds;
      return i;
    }
    const Element& e = s.h.element(n.index());
    i.center = e.center;
    i.normal = e.normal;
    i.area = e.area;
    i.planar = true;
    i.leaf = e.leaf();
    i.material = s.h.patches()[e.patch].material;
    i.object = s.h.patches()[e.patch].object;
    for (int k = 0; k < e.poly.n; ++k) i.bounds.grow(e.poly.v[k]);
    return i;
  }
  std::span<const NodeId> children(NodeId n) const override { return s.h.children(n); }
  std::size_t elementCount() const override { return s.h.elements().size(); }
  std::size_t clusterCount() const override { return s.h.clusters().size(); }
  std::size_t materialCount() const override { return s.scene.materials.size(); }
  MaterialInfo material(std::uint32_t id) const override {
    const Material& m = s.scene.materials[id];
    return {m.diffuse, m.specular, m.exponent, m.emission};
  }

  void markOwned() {
    s.clusterOwned.assign(s.h.clusters().size(), 0);
    if (!s.ext) return;
    for (std::uint32_t p = 0; p < s.h.patches().size(); ++p)
      s.owned[p] = s.ext->simulates(material(s.h.patches()[p].material)) ? 1 : 0;
    // Clusters are built with children after parents: a reverse sweep sees children first.
    for (std::size_t c = s.h.clusters().size(); c-- > 0;)
      for (NodeId k : s.h.cluster(static_cast<std::uint32_t>(c)).children)
        s.clusterOwned[c] |= k.isCluster() ? s.clusterOwned[k.index()] : s.owned[k.index()];
  }

  static PhaseStat stat(const detail::PhaseClock& c) { return {c.wall, c.cpu, c.threads()}; }

  SolveStats solve() {
    SolveStats st;
    auto t0 = std::chrono::steady_clock::now();
    const Hierarchy& h = s.h;
    st.initialPatches = h.patches().size();
    double totalArea = 0.0;
    for (const Patch& p : h.patches()) totalArea += p.area;
    s.minArea = s.opt.minArea > 0.0 ? s.opt.minArea : totalArea * 1e-6;
    s.growArrays();
    markOwned();
    for (const Patch& p : h.patches()) st.emittedW += kPi * s.scene.materials[p.material].emission * p.area;
    s.emittedPower = luminance(st.emittedW);
    s.allocateTables();
    detail::pushPull(s);  // no links yet: cluster intensities from the emitters
    s.links.clear();
    s.links.push_back(Link{h.root(), h.root()});
    double rhoMean = 0.0;
    for (const Patch& p : h.patches()) rhoMean += luminance(s.scene.materials[p.material].diffuse) * p.area;
    rhoMean /= std::max(totalArea, 1e-300);
    // The iteration scheme: shooting passes (shoot.cpp), or the Jacobi gathering loop below.
    if (s.opt.iteration == Iteration::Shoot) detail::shootPasses(s, *this, *progress, st);
    for (int it = 1; s.opt.iteration == Iteration::Gather && it <= s.opt.maxIterations; ++it) {
      auto ti = std::chrono::steady_clock::now();
      progress->phase("iteration " + std::to_string(it) + ": refine");
      std::size_t refined = detail::refineLinks(s);
      if (s.ext) s.ext->attach(*this);
      progress->phase("iteration " + std::to_string(it) + ": gather");
      std::copy(s.B.begin(), s.B.end(), s.Bprev.begin());
      detail::gatherLinks(s);
      detail::pushPull(s);
      double res = 0.0;
      for (std::uint32_t p = 0; p < h.patches().size(); ++p)
        res += h.patches()[p].area * std::abs(luminance(s.B[p] - s.Bprev[p]));
      if (s.ext) res += s.ext->powerChange();  // the extension's light converges too
      IterationStat is;
      is.iteration = it;
      is.residualW = res;
      is.unconvergedW = res * rhoMean / std::max(1e-6, 1.0 - rhoMean);
      is.links = s.links.size();
      is.elements = h.elements().size();
      is.refined = refined;
      is.samples = s.samples.exchange(0);
      st.peakSamples = std::max(st.peakSamples, is.samples);
      is.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - ti).count();
      st.history.push_back(is);
      st.iterations = it;
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "iteration %d: residual %.3e W (%.2e of emitted), unconverged ~%.3e W, links %zu, elements %zu, split %zu",
                    it, res, res / std::max(s.emittedPower, 1e-300), is.unconvergedW, s.links.size(),
                    h.elements().size(), refined);
      progress->note(buf);
      // Convergence as a percentage: how far the residual has fallen, on a log scale, from the
      // first iteration's toward the tolerance.
      double first = st.history.front().residualW, target = s.opt.tolerance * s.emittedPower;
      if (first > target && res > 0.0)
        progress->update(std::clamp(std::log(first / res) / std::log(first / target), 0.0, 1.0));
      if (!std::isfinite(res)) throw std::runtime_error("non-finite radiosity after iteration " + std::to_string(it));
      if (refined == 0 && res <= s.opt.tolerance * s.emittedPower) {
        st.converged = true;
        break;
      }
    }
    if (!st.converged && s.opt.iteration == Iteration::Gather)
      progress->note("NOT CONVERGED after " + std::to_string(s.opt.maxIterations) + " iterations (raise --max-iterations)");
    progress->phase("energy balance");
    detail::AuditResult audit = detail::auditEnergy(s);
    st.absorbedW = audit.absorbedW;
    st.escapedW = audit.escapedW;
    st.backAbsorbedW = audit.backAbsorbedW;
    st.auditStdErrW = audit.escapedStdErrW;
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
const HostView& Solver::view() const { return *impl_; }

}  // namespace hr
