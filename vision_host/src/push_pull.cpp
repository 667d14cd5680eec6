// After a shot: the light each node received travels down to the leaves, where it becomes the next
// shot's unshot light (rho_d E) and joins the radiosity; power and radiosity are pulled back up.
// A cluster's samples (E_perp toward a sender) reach a flat surface with one cosine for all of it and
// a curved leaf with its cosine averaged over 3 x 3 points. Parallel over cluster subtrees.
// With an extension, the same traversal carries the samples (direction and irradiance on the surface)
// down the surfaces it simulates: each leaf's samples of this shot are handed to reflectShot, and
// inner elements and clusters above them are pulled after their children.
#include <tbb/parallel_for.h>

#include <cmath>

#include "state.h"

namespace vision::detail {
namespace {

constexpr double kNode[3] = {0.1127016653792583, 0.5, 0.8872983346207417};
constexpr double kW[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};

struct Chain {
  const std::vector<ClusterSample>* here = nullptr;
  const Chain* up = nullptr;
  Vec3 centre{0.0};  // the cluster's, where its samples were taken
};

/// Irradiance from every sample of the chain on a surface point of unit normal n: sum E_perp max(0, n.w).
Rgb onPlane(const Chain* c, const Vec3& n) {
  Rgb E(0.0);
  for (; c; c = c->up)
    if (c->here)
      for (const ClusterSample& x : *c->here) E += x.Eperp * std::max(0.0, glm::dot(n, x.toSender));
  return E;
}

/// The cosine max(0, n.w) averaged over a leaf (one normal for a flat one, 3 x 3 points on a curved).
double meanCosine(const Surface& sf, const Rect& r, const Vec3& w) {
  if (sf.planar()) return std::max(0.0, glm::dot(sf.normal(0.5, 0.5), w));
  double c = 0.0, a = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double u = r.u0 + kNode[i] * r.du(), v = r.v0 + kNode[j] * r.dv();
      double wq = kW[i] * kW[j] * sf.jacobian(u, v);
      c += wq * std::max(0.0, glm::dot(sf.normal(u, v), w)), a += wq;
    }
  return a > 0.0 ? c / a : 0.0;
}

/// The same irradiance averaged over a curved leaf.
Rgb onLeaf(const Chain* c, const Surface& sf, const Rect& r) {
  Rgb E(0.0);
  double a = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double u = r.u0 + kNode[i] * r.du(), v = r.v0 + kNode[j] * r.dv();
      double w = kW[i] * kW[j] * sf.jacobian(u, v);
      E += w * onPlane(c, sf.normal(u, v)), a += w;
    }
  return a > 0.0 ? E / a : Rgb(0.0);
}

/// The chain's samples as the extension's samples on a leaf (or on a whole flat surface) whose
/// centre is `at`.
void chainSamples(const Chain* c, const Surface& sf, const Rect& r, const Vec3& at, std::vector<hr::IncidentSample>& out) {
  for (; c; c = c->up)
    if (c->here)
      for (const ClusterSample& x : *c->here)
        if (double k = meanCosine(sf, r, x.toSender); k > 0.0) {
          hr::IncidentSample s{x.toSender, x.Eperp * k, x.distance, x.radius, x.senderNormal, x.senderShape};
          hr::aimFrom(s, c->centre, at);
          out.push_back(s);
        }
}

class PushPull {
 public:
  PushPull(State& s, bool push) : s_(s), push_(push) {}

  void cluster(std::uint32_t ci, const Chain* up) {
    hr::markThread(s_.pushThreads);
    Cluster& c = s_.h.clusters()[ci];
    Chain here{&s_.samples[ci], up, c.g.center};
    const std::size_t n = c.clusters.size() + c.surfaces.size();
    auto child = [&](std::size_t k) {
      if (k < c.clusters.size()) {
        cluster(c.clusters[k], &here);
        return;
      }
      Element& e = s_.h.roots()[c.surfaces[k - c.clusters.size()]];
      std::vector<hr::IncidentSample> samples;
      element(e, Rgb(0.0), &here, true, push_ && s_.owned(e) ? &samples : nullptr, false);
    };
    // Subtrees the extension simulates get tasks too: reflection costs far more than a task.
    if (c.surfaceCount > 64 || (s_.ext && s_.ownedCluster[ci]))
      tbb::parallel_for(std::size_t(0), n, child);
    else
      for (std::size_t k = 0; k < n; ++k) child(k);
    c.P = Rgb(0.0);
    for (std::uint32_t k : c.clusters) c.P += s_.h.clusters()[k].P;
    for (std::uint32_t k : c.surfaces) c.P += s_.h.roots()[k].P;
    if (push_ && s_.ext && s_.ownedCluster[ci]) s_.ext->pull(NodeView::cluster(ci), s_.view->children(NodeView::cluster(ci)));
  }

 private:
  /// `samples`: the extension's samples that reached the element from above (null outside the
  /// surfaces it simulates); restored to their length on return.
  /// `layered`: an ancestor's samples were taken by the extension for every leaf below it
  /// (Extension::reflectShared), so a leaf is reflected even with no samples of its own.
  void element(Element& e, Rgb down, const Chain* chain, bool root, std::vector<hr::IncidentSample>* samples,
               bool layered) {
    const Surface& sf = s_.h.surfaces()[e.surface];
    if (root && chain && sf.planar()) {
      if (samples) chainSamples(chain, sf, e.rect, e.g.center, *samples);
      down += onPlane(chain, sf.normal(0.5, 0.5));
      chain = nullptr;
    }
    std::size_t mark = samples ? samples->size() : 0;
    if (samples) samples->insert(samples->end(), e.arrivals.begin(), e.arrivals.end());
    e.arrivals.clear();
    // An inner element of a flat surface offers what reached it to the extension, which may reflect
    // it once for every leaf below (a curved surface's leaves face apart: the extension declines).
    if (samples && !e.leaf() && sf.planar()) {
      const std::size_t left = s_.ext->reflectShared(hr::NodeId{e.id}, *samples);
      layered = layered || left < samples->size();
      samples->resize(left);
      mark = std::min(mark, left);
    }
    const Rgb total = down + e.E;
    e.E = Rgb(0.0);
    if (e.leaf() && !push_) {
      e.P = e.g.area * e.U;  // nothing received yet: a leaf keeps its (emitted) unshot light
    } else if (e.leaf()) {
      Rgb E = total + (chain ? onLeaf(chain, sf, e.rect) : Rgb(0.0));
      Rgb dB = s_.material(e).diffuse * E;
      e.Etot += E;
      e.B += dB;
      e.U = dB;
      e.P = e.g.area * dB;
      if (samples) {
        if (chain) chainSamples(chain, sf, e.rect, e.g.center, *samples);
        s_.handed.fetch_add(samples->size(), std::memory_order_relaxed);
        if (!samples->empty() || layered) s_.ext->reflectShot(hr::NodeId{e.id}, *samples);
      }
    } else {
      Rgb P(0.0), BA(0.0);
      double A = 0.0;
      if (samples) {
        // Each child with its own copy of the samples so far, in parallel (reflection is costly).
        tbb::parallel_for(0, int(e.nkids), [&](int k) {
          std::vector<hr::IncidentSample> mine(*samples);
          for (hr::IncidentSample& x : mine) hr::aimFrom(x, e.g.center, e.kids[k].g.center);
          element(e.kids[k], total, chain, false, &mine, layered);
        });
      } else {
        for (int k = 0; k < e.nkids; ++k) element(e.kids[k], total, chain, false, nullptr, false);
      }
      for (int k = 0; k < e.nkids; ++k) {
        const Element& c = e.kids[k];
        P += c.P, BA += c.g.area * c.B, A += c.g.area;
      }
      e.P = P;
      e.B = A > 0.0 ? BA / A : e.B;
      e.U = A > 0.0 ? P / A : Rgb(0.0);
      if (samples) s_.ext->pull(hr::NodeId{e.id}, s_.view->children(hr::NodeId{e.id}));
    }
    if (samples) samples->resize(mark);
    e.sendKids = e.nkids;
  }

  State& s_;
  const bool push_;
};

}  // namespace

double pushPull(State& s, bool push) {
  if (s.h.clusters().empty()) return 0.0;
  PushPull(s, push).cluster(0, nullptr);
  buildTables(s);
  return hr::luminance(s.h.clusters()[0].P);
}

void indexClusters(State& s) {
  const auto& cl = s.h.clusters();
  s.first.assign(cl.size(), 0);
  s.order.clear();
  s.areaPrefix.assign(1, 0.0);
  // Depth first, children in order: every cluster's surfaces are contiguous.
  auto visit = [&](auto&& self, std::uint32_t c) -> void {
    s.first[c] = static_cast<std::uint32_t>(s.order.size());
    for (std::uint32_t k : cl[c].clusters) self(self, k);
    for (std::uint32_t k : cl[c].surfaces) {
      s.order.push_back(k);
      s.areaPrefix.push_back(s.areaPrefix.back() + s.h.roots()[k].g.area);
    }
  };
  if (!cl.empty()) visit(visit, 0);
  s.samples.assign(cl.size(), {});
}

}  // namespace vision::detail
