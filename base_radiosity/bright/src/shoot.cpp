// Shooting iterations (--iteration shoot): progressive hierarchical radiosity in passes (paper §3.4;
// Stamminger et al. 1998). Every element keeps unshot radiosity beside its radiosity, and an
// extension keeps unshot light beside its total light. One pass:
//  1. every root patch whose unshot power is at least opt.shootFraction of the largest shoots,
//     through the largest cluster all of whose patches shoot where there is one (choose);
//  2. each shooter's links (kept from its earlier passes, else one link to the root cluster) are
//     refined by the usual oracle, which reads the shooters' unshot light (SolverState::shooting);
//  3. the unshot light travels along them (gatherLinks; the gather hook sees this pass's samples);
//  4. the shooters' unshot light is cleared (host and extension);
//  5. what arrived is pushed down (PushMode::ShootLeaves): it joins radiosity and unshot, and the
//     extension reflects its samples and drops them. This goes in batches of receiver groups of at
//     most kBatchSamples samples into simulated subtrees, so that a pass never holds all its samples
//     at once (paper §3.4: shooting reflects and drops samples as they arrive; a pass of many
//     shooters held 0.40 of a gathering iteration's samples on the glossy sphere). All the pass's
//     links were gathered before the first batch, from what the shooters held at the pass's start,
//     so batching changes no light sent (a link's (dir, E) is a field every link keeps anyway);
//     only a leaf reached by several batches reflects them in parts and sums the parts. A pass that
//     fits in one batch (every diffuse pass) is pushed and pulled in one traversal (PushMode::Shoot).
//  6. one pull (PushMode::ShootPull) visits only the subtrees the pass lit and the paths up from them
//     and from the shooters: elsewhere nothing changed, and re-pulling it cost most of a pass (the
//     glossy sphere: 65 % of the solve in push/pull, its clusters' distributions summed again every
//     pass).
// All shooters of a pass send what they held at its start, so the pass is one parallel step; shooters
// are taken in tree and patch order and refinement is deterministic, so passes do not depend on the
// thread count. A cluster shooter sends its patches' unshot light as a gathering cluster sends
// radiosity (its table or cosine lobes, pulled from unshot radiosity in a shooting solve:
// SolverState::clusterSource). Links are kept per shooter: a later pass from the same shooter
// reuses them, refined for its strongest shot (the first, as a rule). Refining afresh for each
// weaker shot instead (link-less) lets every weak shot err by up to the threshold again: the glossy
// sphere's balance went from 0.2 % to -1.9 %. Stops when the unshot power left is below tolerance
// x emitted (converged) or after maxIterations passes (not converged; the power left is reported).
// The oracle, the energy audit and the outputs are the gathering ones.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "solver_state.h"

namespace hr::detail {
namespace {

// Samples one push carries at most (unless a single receiver's links are more): 1024 x 24 bytes. A
// batch costs a traversal of the subtrees it lit and a leaf reached by k batches reflects k times;
// smaller batches hold less for more of both (docs/results.md has the glossy sphere's figures).
constexpr std::size_t kBatchSamples = 1024;

/// A patch's unshot power, W (luminance): its host light plus the extension's.
double unshotPower(const SolverState& s, std::uint32_t p) {
  double w = luminance(s.U[p]) * s.openArea(p);  // (the root element of patch p has index p)
  if (s.ext && s.owned[p]) w += luminance(s.ext->unshotPower(NodeId{p}));
  return w;
}

/// Clears an element subtree's unshot radiosity.
void clearUnshot(SolverState& s, std::uint32_t e) {
  s.U[e] = Rgb(0.0);
  s.Umin[e] = s.Umax[e] = 0.0f;
  const Element& el = s.h.element(e);
  if (!el.leaf())
    for (std::uint32_t k = 0; k < 4; ++k) clearUnshot(s, el.firstChild + k);
}

double meanReflectance(const SolverState& s) {
  double rho = 0.0, area = 0.0;
  for (const Patch& p : s.h.patches()) rho += luminance(s.scene.materials[p.material].diffuse) * p.area, area += p.area;
  return rho / std::max(area, 1e-300);
}

class Shooter {
 public:
  Shooter(SolverState& s, const HostView& view, Progress& progress, SolveStats& st)
      : s_(s), view_(view), progress_(progress), st_(st), stored_(s.h.patches().size() + s.h.clusters().size()),
        power_(s.h.patches().size()) {}

  void run() {
    const double rho = meanReflectance(s_), target = s_.opt.tolerance * s_.emittedPower;
    double left = measure();
    const double first = left;
    for (int pass = 1; pass <= s_.opt.maxIterations && left > target; ++pass) {
      auto t0 = std::chrono::steady_clock::now();
      progress_.phase("pass " + std::to_string(pass) + ": shoot");
      const Shooters shooters = choose();
      std::size_t refined = shoot(shooters);
      progress_.phase("pass " + std::to_string(pass) + ": push/pull");
      const std::size_t handed = s_.samples.exchange(0);  // by the gather hook, the whole pass's
      Batches b = pushAndPull();
      left = measure();
      if (!std::isfinite(left)) throw std::runtime_error(nonFiniteWhere(s_, "shooting pass " + std::to_string(pass)));
      IterationStat is;
      is.iteration = pass;
      is.residualW = left;
      is.unconvergedW = left * rho / std::max(1e-6, 1.0 - rho);
      is.links = links_;
      is.elements = s_.h.elements().size();
      is.refined = refined;
      is.shooters = shooters.count();
      is.pushedPatches = s_.h.patches().size() - s_.pushSkipped.load();
      is.samples = handed;
      is.samplesAtOnce = b.most;
      is.batches = b.count;
      is.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      st_.history.push_back(is);
      st_.iterations = pass;
      st_.peakSamples = std::max(st_.peakSamples, is.samples);
      st_.peakSamplesAtOnce = std::max(st_.peakSamplesAtOnce, is.samplesAtOnce);
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "pass %d: %zu shooter(s), unshot %.3e W (%.2e of emitted), links %zu, elements %zu, split %zu", pass,
                    shooters.count(), left, left / std::max(s_.emittedPower, 1e-300), is.links, is.elements, refined);
      progress_.note(buf);
      if (first > target && left > 0.0)
        progress_.update(std::clamp(std::log(first / left) / std::log(first / target), 0.0, 1.0));
    }
    st_.converged = left <= target;
    st_.unshotW = left;
    if (!st_.converged) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "NOT CONVERGED after %d passes: %.3e W unshot (%.2e of emitted; raise --max-iterations)",
                    st_.iterations, left, left / std::max(s_.emittedPower, 1e-300));
      progress_.note(buf);
    }
    // The links of every shooter, for the statistics (and nothing else: no more passes follow).
    s_.links.clear();
    s_.links.reserve(links_);
    for (auto& v : stored_) s_.links.insert(s_.links.end(), v.begin(), v.end()), v = {};
  }

 private:
  struct Batches {
    std::size_t count = 0, most = 0;  // pushes; the most samples one of them carried
  };

  /// Adds the pass's gathered light to the leaves in batches of consecutive receiver groups (the
  /// order refinement sorted them in: the same for any thread count), each holding at most
  /// kBatchSamples samples into simulated subtrees unless one group alone holds more, then pulls
  /// once. A pass that fits in one batch (every diffuse pass: no samples) is pushed and pulled in
  /// one traversal, as before batching.
  Batches pushAndPull() {
    const std::size_t groups = std::max<std::size_t>(s_.groupStart.size(), 1) - 1;
    std::vector<std::size_t> ends;  // each batch's end group; batch k starts where k - 1 ended
    Batches b;
    std::size_t held = 0;
    for (std::size_t g = 0; g < groups; ++g) {
      const NodeId r = s_.links[s_.groupStart[g]].receiver;
      const std::size_t n = s_.ext && s_.isOwned(r) ? s_.groupStart[g + 1] - s_.groupStart[g] : 0;
      if (held > 0 && held + n > kBatchSamples) ends.push_back(g), b.most = std::max(b.most, held), held = 0;
      held += n;
    }
    ends.push_back(groups), b.most = std::max(b.most, held);
    b.count = ends.size();
    if (ends.size() == 1) {
      pushPull(s_, PushMode::Shoot);
      return b;
    }
    for (std::size_t k = 0; k < ends.size(); ++k) pushPull(s_, PushMode::ShootLeaves, k == 0 ? 0 : ends[k - 1], ends[k]);
    pushPull(s_, PushMode::ShootPull);
    return b;
  }

  /// Every patch's unshot power; returns their sum, W (luminance).
  double measure() {
    tbb::parallel_for(std::size_t(0), power_.size(), [&](std::size_t p) { power_[p] = unshotPower(s_, std::uint32_t(p)); });
    double sum = 0.0;  // in patch order: the same for any thread count
    for (double w : power_) sum += w;
    return sum;
  }

  /// A pass's shooters: clusters, and patches outside them.
  struct Shooters {
    std::vector<std::uint32_t> clusters, patches;  // patches: shooting alone, in patch order
    std::vector<std::uint32_t> all;                // every patch shot, alone or in a cluster
    std::size_t count() const { return clusters.size() + patches.size(); }
  };

  /// The pass's shooters. Patches whose unshot power is at least opt.shootFraction of the largest
  /// shoot (smaller fractions shoot more per pass, toward a Jacobi sweep over the unshot light: fewer
  /// passes, more samples held at once; 1 shoots the strongest alone; docs/results.md). Where every
  /// patch of a cluster shoots and the extension simulates none of them, the cluster shoots as one,
  /// as a gathering receiver sees it: a lamp of 16 patches sending a sixteenth of its light from each
  /// refined its receivers as a sixteenth of the lamp does, 3.4 times more coarsely than gathering
  /// (three lights: 5 % apart, now 1 %, the seeds' own spread). Clusters that also hold dark
  /// patches are not taken: they span more than their light (a closed room's shooters in one cluster
  /// with a dark box 10 m away lost 1.1 % of the power, 0.67 % without). Clusters are taken from the
  /// top, so a shooter cluster is the largest such.
  Shooters choose() const {
    const double most = *std::max_element(power_.begin(), power_.end());
    const auto& order = s_.h.patchOrder();
    std::vector<std::uint8_t> picked(power_.size(), 0);
    // Prefix counts over cluster order: patches that may shoot in a cluster (shooting, and not
    // simulated by the extension), and patches shooting.
    std::vector<std::uint32_t> fits(order.size() + 1, 0), shoots(order.size() + 1, 0);
    for (std::size_t i = 0; i < order.size(); ++i) {
      const std::uint32_t p = order[i];
      picked[p] = power_[p] > 0.0 && power_[p] >= s_.opt.shootFraction * most;
      const bool simulated = s_.ext && s_.owned[p];
      fits[i + 1] = fits[i] + (picked[p] && !simulated ? 1 : 0);
      shoots[i + 1] = shoots[i] + picked[p];
    }
    Shooters out;
    std::vector<std::uint8_t> inCluster(power_.size(), 0);
    std::vector<std::uint32_t> stack{s_.h.root().index()};
    while (!stack.empty()) {
      const std::uint32_t c = stack.back();
      stack.pop_back();
      const Cluster& cl = s_.h.cluster(c);
      const std::uint32_t n = cl.patchEnd - cl.patchBegin, k = shoots[cl.patchEnd] - shoots[cl.patchBegin];
      if (k == 0) continue;
      if (n > 1 && fits[cl.patchEnd] - fits[cl.patchBegin] == n) {
        out.clusters.push_back(c);
        for (std::uint32_t i = cl.patchBegin; i < cl.patchEnd; ++i) inCluster[order[i]] = 1;
        continue;
      }
      for (auto it = cl.children.rbegin(); it != cl.children.rend(); ++it)
        if (it->isCluster()) stack.push_back(it->index());
    }
    for (std::uint32_t p = 0; p < power_.size(); ++p) {
      if (!picked[p]) continue;  // (a shooter cluster's patches all shoot)
      out.all.push_back(p);
      if (!inCluster[p]) out.patches.push_back(p);
    }
    return out;
  }

  /// Refines the shooters' links, sends their unshot light along them and clears it; returns splits.
  std::size_t shoot(const Shooters& shooters) {
    s_.links.clear();
    // Links are kept per shooter: stored_[p] for patch p shooting alone, stored_[P + c] for cluster
    // c (refined for its own strongest shot; a patch may hold both kinds for when it shoots either way).
    const std::size_t P = s_.h.patches().size();
    std::vector<std::uint32_t> keyOfPatch(P, ~0u);
    auto take = [&](std::size_t key, NodeId sender) {
      // Uncounted before it is stored: a first shot's root link was never counted (a lamp facing
      // away from everything loses it to refinement, and the count wrapped below zero).
      links_ -= stored_[key].size();
      if (stored_[key].empty()) stored_[key].push_back(Link{sender, s_.h.root()});
      s_.links.insert(s_.links.end(), stored_[key].begin(), stored_[key].end());
      stored_[key] = {};
    };
    for (std::uint32_t c : shooters.clusters) {
      const Cluster& cl = s_.h.cluster(c);
      for (std::uint32_t i = cl.patchBegin; i < cl.patchEnd; ++i)
        keyOfPatch[s_.h.patchOrder()[i]] = std::uint32_t(P + c);
      take(P + c, NodeId{c | NodeId::kClusterBit});
    }
    for (std::uint32_t p : shooters.patches) keyOfPatch[p] = p, take(p, NodeId{p});
    s_.shooting = true;
    std::size_t refined = refineLinks(s_);
    if (s_.ext) s_.ext->attach(view_);
    gatherLinks(s_);
    s_.shooting = false;
    s_.passShooters = shooters.all;
    tbb::parallel_for(std::size_t(0), shooters.all.size(), [&](std::size_t i) {
      const std::uint32_t p = shooters.all[i];
      clearUnshot(s_, p);
      if (s_.ext && s_.owned[p]) s_.ext->shot(NodeId{p});  // (a patch the extension simulates shoots alone)
    });
    // Back to their shooters, in the order refinement left them: a link's sender lies in one shooter
    // (an element in its patch, a cluster in a shooter cluster, any of whose patches names it).
    for (const Link& l : s_.links) {
      const NodeId n = l.sender;
      const std::uint32_t p =
          n.isCluster() ? s_.h.patchOrder()[s_.h.cluster(n.index()).patchBegin] : s_.h.element(n.index()).patch;
      stored_[keyOfPatch[p]].push_back(l);
    }
    links_ += s_.links.size();
    return refined;
  }

  SolverState& s_;
  const HostView& view_;
  Progress& progress_;
  SolveStats& st_;
  std::vector<std::vector<Link>> stored_;  // per patch, then per cluster: the links it shoots along
  std::vector<double> power_;              // per patch: unshot power, W (luminance)
  std::size_t links_ = 0;                  // links stored over all shooters
};

}  // namespace

void shootPasses(SolverState& s, const HostView& view, Progress& progress, SolveStats& st) {
  if (s.ext && !s.ext->canShoot())
    throw InputError("--iteration shoot: --algorithm " + std::string(s.ext->name()) + " cannot shoot (it gathers only)");
  st.iteration = Iteration::Shoot;
  st.shootFraction = s.opt.shootFraction;
  Shooter(s, view, progress, st).run();
}

}  // namespace hr::detail
