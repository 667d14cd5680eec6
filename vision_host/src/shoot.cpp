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
//
// Where the light an element receives lands inside it matters too: the push hands it down evenly.
// Accepted element-to-element interactions are held until the receiver's list is done; how unevenly
// their sum falls over the receiver's quarters is held to the same budget as one interaction's gap
// (settle), and what stays is given to the receiver's children quarter by quarter (place).
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <utility>

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
      if (s_.owned(*r.e) && est.E != Rgb(0.0))
        r.e->arrivals.push_back(
            {est.toSender, est.E, est.distance, est.radius, est.senderNormal, est.senderShape});
    } else if (est.E != Rgb(0.0))
      s_.samples[r.cluster].push_back(
          {est.toSender, est.E, est.distance, est.radius, est.senderNormal, est.senderShape});
  }

  struct Pending {
    Sender x;
    Estimate est;
  };
  /// Each quarter's irradiance over the receiver's mean, from the estimate's form factors.
  static void quarterShares(const Estimate& est, double out[4]) {
    const double F = 0.25 * (est.quarterF[0] + est.quarterF[1] + est.quarterF[2] + est.quarterF[3]);
    for (int q = 0; q < 4; ++q) out[q] = F > 0.0 ? est.quarterF[q] / F : 1.0;
  }
  /// Irradiance an estimate brings each quarter of its receiver (luminance, W/m^2).
  static void quarterE(const Pending& p, double out[4]) {
    quarterShares(p.est, out);
    for (int q = 0; q < 4; ++q) out[q] *= hr::luminance(p.est.E);
  }
  /// Each interaction's gap is held to the budget, but near a concave edge every sender but the
  /// adjacent face lights the receiver's edge side less, so hundreds of interactions, each within
  /// budget, misplace light the same way (first shot in a sphere inside a closed box at eps 1e-3: the
  /// rows along the edges 5 % high, the next rows 5 % low; refining senders only makes more of them).
  /// So the unevenness of their sum over the receiver's quarters (mean deviation, times the area, W)
  /// is held to the budget: while it is over, the interaction adding most to it is handed down to the
  /// children, with the visible fraction traced here (re-tracing few rays per child lost 0.5 % of the
  /// furnace's light). Parts of a handed-down sender keep that fraction.
  void settle(const Receiver& r, double budget, std::vector<Pending>& held, std::vector<Sender>& down) {
    if (held.empty()) return;
    double sum[4] = {0.0, 0.0, 0.0, 0.0}, one[4];
    std::vector<std::pair<double, std::size_t>> order;
    for (std::size_t k = 0; k < held.size(); ++k) {
      quarterE(held[k], one);
      double lo = one[0], hi = one[0];
      for (int q = 0; q < 4; ++q) sum[q] += one[q], lo = std::min(lo, one[q]), hi = std::max(hi, one[q]);
      order.push_back({hi - lo, k});
    }
    const double area = r.g(s_.h).area;
    auto misplaced = [&] {
      const double mean = 0.25 * (sum[0] + sum[1] + sum[2] + sum[3]);
      double d = 0.0;
      for (int q = 0; q < 4; ++q) d += 0.25 * std::abs(sum[q] - mean);
      return area * d;
    };
    std::vector<char> handed(held.size(), 0);
    if (misplaced() > budget) {
      std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
      for (const auto& o : order) {
        quarterE(held[o.second], one);
        for (int q = 0; q < 4; ++q) sum[q] -= one[q];
        handed[o.second] = 1;
        if (misplaced() <= budget) break;
      }
    }
    Rgb kept[4] = {Rgb(0.0), Rgb(0.0), Rgb(0.0), Rgb(0.0)};
    for (std::size_t k = 0; k < held.size(); ++k) {
      const Estimate& est = held[k].est;
      if (handed[k]) {
        down.push_back(std::move(held[k].x)), down.back().V = est.V;
        continue;
      }
      quarterShares(est, one);
      for (int q = 0; q < 4; ++q) kept[q] += est.E * one[q];
    }
    held.clear();
    place(*r.e, kept, !down.empty());
  }
  /// What stays at a receiver goes to it, or, when it has (or is about to get) children, to each
  /// child as the quarters it covers received it, scaled so that the power is the receiver's (the
  /// quarters' means are quadrature estimates). Within a child it is even again.
  void place(Element& e, const Rgb kept[4], bool splits) {
    const Rgb mean = 0.25 * (kept[0] + kept[1] + kept[2] + kept[3]);
    if (e.nkids == 0 && splits) s_.h.subdivide(e);
    if (e.nkids == 0) {
      e.E += mean;
      return;
    }
    const double um = 0.5 * (e.rect.u0 + e.rect.u1), vm = 0.5 * (e.rect.v0 + e.rect.v1);
    Rgb child[4], power(0.0);
    for (int k = 0; k < e.nkids; ++k) {
      const Rect& c = e.kids[k].rect;
      const bool uLo = c.u1 <= um, uHi = c.u0 >= um, vLo = c.v1 <= vm, vHi = c.v0 >= vm;
      Rgb sum(0.0);
      int n = 0;
      for (int q = 0; q < 4; ++q)
        if (!((q & 1) ? uLo : uHi) && !((q & 2) ? vLo : vHi)) sum += kept[q], ++n;
      child[k] = n > 0 ? sum / double(n) : mean;
      power += e.kids[k].g.area * child[k];
    }
    for (int c = 0; c < 3; ++c) {
      const double f = power[c] > 0.0 ? e.g.area * mean[c] / power[c] : 1.0;
      for (int k = 0; k < e.nkids; ++k) e.kids[k].E[c] += f * child[k][c];
    }
  }

  void receive(const Receiver& r, std::vector<Sender> work) {
    hr::markThread(s_.shootThreads);
    const Geometry& rg = r.g(s_.h);
    const bool rSplits = canSplit(r);
    // The gap is held partly in radiosity (bounded radiosity bounds B): eps times the emitted power,
    // scaled by this receiver's share of the scene's area but by no less than kAreaFloor. A power
    // budget alone let a small element get a whole interaction's gap (corners of a closed cube read
    // 21 % high at eps 1e-3); the pure radiosity budget did not finish the Cornell box in 10 minutes (6 s
    // before; 37 s with the floor). The unevenness of the light kept here gets the same budget
    // (settle): the pure per-area one took the Cornell box from 10 s to 113 s (107k elements).
    const double limit = s_.threshold * std::max(rg.area / std::max(s_.h.totalArea(), 1e-300), kAreaFloor);
    std::vector<Sender> down;
    std::vector<Pending> held;  // accepted element-to-element interactions, placed by settle()
    ReceiverPoints points;      // r's quadrature points, for all its senders
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
      // A sharply reflecting receiver misplaces the image of a sender it sees wider than its lobe (the
      // sender's light arrives as one direction): that share of what it can receive counts too.
      if (gap <= limit && !s_.surfaceReflector.empty()) {
        const hr::Reflector& rf = r.e ? s_.surfaceReflector[r.e->surface] : s_.clusterReflector[r.cluster];
        const double d = glm::length(x.g.center - rg.center);
        const double share = hr::misplacedReflection(rf, 2.0 * std::max(x.g.radius, rg.radius), d);
        if (share > 0.0) gap += share * rg.area * kb.kmax * (phi + (x.owned ? hr::luminance(x.X) : 0.0)) / hr::kPi;
      }
      const bool xSplits = canSplit(x);
      if (gap <= limit || (!xSplits && !rSplits)) {
        const Estimate est = estimate(s_, x, r, &points);
        ++count_;
        // Visibility widens the gap: a shadow boundary across the pair misplaces up to the smaller of
        // its lit and its hidden part; too few agreeing rays leave the fraction itself uncertain.
        const double shadow = est.mixed ? 2.0 * std::min(est.V, 1.0 - est.V) * est.unoccluded : 0.0;
        const bool sure = est.sigma * est.unoccluded <= s_.visTolerance;
        if ((gap + shadow <= limit && sure) || (!xSplits && !rSplits)) {
          if (rSplits && est.quarters && !x.owned && !s_.owned(*r.e))
            held.push_back(Pending{std::move(x), est});
          else
            accept(r, est);
          continue;
        }
      }
      // The larger node is split; a receiver by handing the sender down to its children.
      if (xSplits && (!rSplits || x.g.radius > rg.radius)) {
        const std::size_t from = work.size();
        childrenOf(x, work);
        for (std::size_t k = from; k < work.size(); ++k) work[k].V = x.V;  // a handed-down sender's parts keep its V
      } else {
        down.push_back(std::move(x));
      }
    }
    settle(r, limit, held, down);
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
