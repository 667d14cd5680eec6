// Link-less shooting (Stamminger, Schirmacher, Slusallek, Seidel 1998): each shot sends every node's
// unshot light, and its interactions are derived top-down from the root cluster's interaction with
// itself, used once and forgotten. Since the unshot power falls with every bounce, later shots need
// ever fewer interactions; memory holds nodes and their light, never links.
//
// The traversal is receiver-driven: a task owns one receiver and a work list of senders. For each
// sender it bounds the power the receiver may get (bounds.cpp); an interaction whose gap between
// upper and lower bound is within the threshold is estimated (transfer.cpp) and added to the
// receiver; otherwise the larger node is split: a sender into its children (a leaf into parts, which
// creates no node), a receiver by handing the sender down to its children, each visited by a task of
// its own. So every receiver is written by one task only, in list order: the result is the same for
// any thread count, and no lock is taken.
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>

#include "state.h"

namespace vision::detail {
namespace {

/// Smallest share of the power budget a receiver gets (see receive()).
constexpr double kAreaFloor = 1.0 / 64.0;

class Shot {
 public:
  explicit Shot(State& s) : s_(s), maxLevel_(2 * std::max(0, s.opt.maxLevel)) {}
  std::uint64_t run() {
    Receiver root;
    root.cluster = 0;
    receive(root, {ofCluster(0)});
    return count_.load();
  }

 private:
  Sender ofCluster(std::uint32_t c) const {
    Sender x;
    x.cluster = c;
    x.g = s_.h.clusters()[c].g;
    x.P = s_.h.clusters()[c].P;
    extensionSender(s_, x);
    return x;
  }
  Sender ofElement(const Element& e) const {
    Sender x;
    x.e = &e, x.rect = e.rect, x.level = e.level, x.g = e.g, x.P = e.P;
    x.U = e.g.area > 0.0 ? e.P / e.g.area : Rgb(0.0);
    extensionSender(s_, x);
    return x;
  }
  static void keep(Sender x, std::vector<Sender>& out) {
    if (!x.dark()) out.push_back(std::move(x));
  }
  /// An element below the depth and area limits may split (levels count halvings of the area).
  bool splittable(std::uint16_t level, double area) const { return level < maxLevel_ && 0.25 * area >= s_.minArea; }
  bool canSplit(const Sender& x) const {
    if (x.cluster != hr::kNone) return true;
    if (!x.part && x.e->sendKids > 0) return true;
    return splittable(x.level, x.g.area);
  }
  bool canSplit(const Receiver& r) const { return !r.e || r.e->nkids > 0 || splittable(r.e->level, r.e->g.area); }

  void childrenOf(const Sender& x, std::vector<Sender>& out) const {
    if (x.cluster != hr::kNone) {
      const Cluster& c = s_.h.clusters()[x.cluster];
      for (std::uint32_t k : c.clusters) keep(ofCluster(k), out);
      for (std::uint32_t k : c.surfaces) keep(ofElement(s_.h.roots()[k]), out);
      return;
    }
    if (!x.part && x.e->sendKids > 0) {
      for (int k = 0; k < x.e->sendKids; ++k) keep(ofElement(x.e->kids[k]), out);
      return;
    }
    // A leaf (or a part of one) shoots as the parts it would split into, each with its uniform light.
    const Surface& sf = s_.h.surfaces()[x.e->surface];
    Split sp = splitOf(sf, x.rect);
    for (int k = 0; k < sp.count; ++k) {
      Sender p;
      p.e = x.e, p.part = true, p.rect = sp.kids[k];
      p.level = std::uint16_t(x.level + sp.levelStep);
      p.g = measure(sf, p.rect);
      p.U = x.U, p.P = p.g.area * x.U;
      extensionSender(s_, p);
      keep(std::move(p), out);
    }
  }

  void accept(const Receiver& r, const Estimate& est) {
    if (r.e) {
      r.e->E += est.E;
      if (s_.owned(*r.e) && est.E != Rgb(0.0)) r.e->arrivals.push_back({est.toSender, est.E});
    } else if (est.E != Rgb(0.0))
      s_.samples[r.cluster].push_back({est.toSender, est.E});
  }

  void receive(const Receiver& r, std::vector<Sender> work) {
    hr::markThread(s_.shootThreads);
    const Geometry& rg = r.g(s_.h);
    const bool rSplits = canSplit(r);
    // The gap is held partly in radiosity (bounded radiosity bounds B): eps times the emitted power,
    // scaled by this receiver's share of the scene's area but by no less than kAreaFloor. A power
    // budget alone let a small element get a whole interaction's gap (corners of a closed cube read
    // 21 % high at eps 1e-3); the pure radiosity budget did not finish the Cornell box in 10 minutes (6 s
    // before; 37 s with the floor).
    const double limit = s_.threshold * std::max(rg.area / std::max(s_.h.totalArea(), 1e-300), kAreaFloor);
    std::vector<Sender> down;
    while (!work.empty()) {
      Sender x = std::move(work.back());
      work.pop_back();
      // A flat or convex surface never lights itself.
      if (x.cluster == hr::kNone && r.e && x.e->surface == r.e->surface && !s_.h.surfaces()[r.e->surface].concave()) continue;
      const double phi = hr::luminance(x.P);
      if (!(phi > 0.0) && !x.owned) continue;
      const KernelBounds kb = kernelBounds(x.g, rg);
      if (!(kb.kmax > 0.0)) continue;
      double gap = kb.overlap ? std::numeric_limits<double>::infinity() : rg.area * (kb.kmax - kb.kmin) * phi / hr::kPi;
      // The extension's share: first from its peak alone (cheap), over the cone toward the receiver
      // only when that would split.
      if (x.owned && gap <= limit) {
        const double lambertian = gap;
        gap = lambertian + extensionGap(s_, x, rg, kb, true);
        if (gap > limit) gap = lambertian + extensionGap(s_, x, rg, kb, false);
      }
      const bool xSplits = canSplit(x);
      if (gap <= limit || (!xSplits && !rSplits)) {
        const Estimate est = estimate(s_, x, r);
        ++count_;
        // Visibility widens the gap: a shadow boundary across the pair misplaces up to the smaller of
        // its lit and its hidden part; too few agreeing rays leave the fraction itself uncertain.
        const double shadow = est.mixed ? 2.0 * std::min(est.V, 1.0 - est.V) * est.unoccluded : 0.0;
        const bool sure = est.sigma * est.unoccluded <= s_.visTolerance;
        if ((gap + shadow <= limit && sure) || (!xSplits && !rSplits)) {
          accept(r, est);
          continue;
        }
      }
      // The larger node is split; a receiver by handing the sender down to its children.
      if (xSplits && (!rSplits || x.g.radius > rg.radius))
        childrenOf(x, work);
      else
        down.push_back(std::move(x));
    }
    if (down.empty()) return;
    std::vector<Receiver> kids;
    if (r.e) {
      if (r.e->nkids == 0) s_.h.subdivide(*r.e);
      for (int k = 0; k < r.e->nkids; ++k) kids.push_back(Receiver{hr::kNone, &r.e->kids[k]});
    } else {
      const Cluster& c = s_.h.clusters()[r.cluster];
      for (std::uint32_t k : c.clusters) kids.push_back(Receiver{k, nullptr});
      for (std::uint32_t k : c.surfaces) kids.push_back(Receiver{hr::kNone, &s_.h.roots()[k]});
    }
    // Tasks only where there is work enough to share; each child gets its own copy of the list.
    if (down.size() * kids.size() >= 8)
      tbb::parallel_for(std::size_t(0), kids.size(), [&](std::size_t k) { receive(kids[k], down); });
    else
      for (const Receiver& k : kids) receive(k, down);
  }

  State& s_;
  const int maxLevel_;
  std::atomic<std::uint64_t> count_{0};
};

}  // namespace

std::uint64_t shoot(State& s) {
  for (auto& v : s.samples) v.clear();
  if (s.h.clusters().empty()) return 0;
  return Shot(s).run();
}

}  // namespace vision::detail
