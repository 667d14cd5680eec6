// Gathering along links, and push/pull. Gathering is parallel over receivers. Push/pull walks the
// cluster tree in parallel over subtrees: each cluster's links' normal irradiance travels down as a
// chain of link ranges (no copies), each element subtree takes its irradiance with its own cosine,
// radiosity is pulled up the quadtrees and cluster intensity tables are summed bottom-up. With an
// extension, the same traversal carries Illumination Samples down subtrees it simulates and calls
// the reflection and pull hooks (its light adds to the host's; the host's own values are unchanged).
// Gathering replaces each leaf's light by what this iteration brought (Jacobi); a shooting pass adds
// what it brought to both the radiosity and the unshot radiosity (and the extension's reflectShot).
// A shooting pass may add its light in batches of receiver groups (leaves only, no pull), so that
// only one batch's samples are packed and carried down at once, and pull once after the last.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <limits>

#include "solver_state.h"

namespace hr::detail {

void gatherLinks(SolverState& s) {
  PhaseTimer t(s.clkGather);
  // Cleared in parallel too: on the Cornell box a sweep's gather is ~2 ms, and a serial clear of
  // every element's irradiance was a tenth of it.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.Eg.size(), 8192), [&](const auto& r) {
    std::fill(s.Eg.begin() + std::ptrdiff_t(r.begin()), s.Eg.begin() + std::ptrdiff_t(r.end()), Rgb(0.0));
  });
  if (s.groupStart.size() < 2) return;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.groupStart.size() - 1, 16), [&](const auto& r) {
    s.clkGather.sawThread();
    for (std::size_t g = r.begin(); g != r.end(); ++g) {
      Rgb sum(0.0);
      NodeId recv = s.links[s.groupStart[g]].receiver;
      for (std::uint32_t i = s.groupStart[g]; i < s.groupStart[g + 1]; ++i) {
        Link& l = s.links[i];
        Rgb e = double(l.coef) * s.senderValue(l);  // may read the extension's share kept in E
        l.E = glm::vec3(e);
        l.extCache = 0;
        sum += e;
      }
      if (!recv.isCluster()) s.Eg[recv.index()] = sum;
    }
  });
  // Link gather hook: the receivers' Illumination Samples, for subtrees the extension simulates.
  if (s.ext) callGatherHooks(s);
}

namespace {

/// The octahedral map's bin directions, once, as floats laid out for the vectoriser: adding a patch's
/// cosine lobe to a cluster table is the inner loop of the pull (53 k patches x 256 bins on the
/// Soda Shoppe), and decoding each bin direction there cost most of push/pull.
struct BinDirections {
  alignas(64) float x[OctaMap::kBins], y[OctaMap::kBins], z[OctaMap::kBins];
  BinDirections() {
    for (int i = 0; i < OctaMap::kBins; ++i) {
      Vec3 d = OctaMap::binDirection(i);
      x[i] = float(d.x), y[i] = float(d.y), z[i] = float(d.z);
    }
  }
};
const BinDirections kBinDirs;

/// Adds the intensity of a Lambertian patch, rad * max(0, n . w) W/sr, to every bin of a planar
/// table.
void addCosineLobe(float* t, const Vec3& n, const Rgb& rad) {
  const float nx = float(n.x), ny = float(n.y), nz = float(n.z);
  const float r = float(rad.x), g = float(rad.y), b = float(rad.z);
  constexpr int K = OctaMap::kBins;
  for (int i = 0; i < K; ++i) {
    float c = std::max(0.0f, nx * kBinDirs.x[i] + ny * kBinDirs.y[i] + nz * kBinDirs.z[i]);
    t[i] += r * c;
    t[K + i] += g * c;
    t[2 * K + i] += b * c;
  }
}

/// A cluster's incoming light, as float arrays for the vectoriser: unit directions toward the
/// senders and normal irradiance (W/m^2) per link.
struct ClusterSamples {
  std::vector<float> dx, dy, dz, er, eg, eb, dist, radius;
  // The sender's element index, for its normal and shape (kNone: a cluster); only where samples are
  // carried. One index, not the 28 bytes it names: the glossy Soda Shoppe holds 0.6 M samples at once.
  std::vector<std::uint32_t> sender;
  Vec3 centre{0.0};
};

/// The samples arriving at a cluster and at all its ancestors: one cluster per level.
struct SampleChain {
  const ClusterSamples* here = nullptr;
  const SampleChain* parent = nullptr;
};

class PushPull {
 public:
  static constexpr std::uint32_t kSerialPatches = 512;

  PushPull(SolverState& s, PushMode mode, std::size_t groupBegin, std::size_t groupEnd)
      : s_(s), shoot_(mode != PushMode::Gather), prune_(shoot_ && !s.opt.testOnlyPushEverything),
        leavesOnly_(mode == PushMode::ShootLeaves), pullOnly_(mode == PushMode::ShootPull),
        carry_(s.ext && !s.ext->reflectsInGather() && !pullOnly_),
        g0_(std::min(groupBegin, groupCount())), g1_(std::min(groupEnd, groupCount())) {
    // A batch adds the gathered irradiance of its own element receivers only.
    if (leavesOnly_) {
      inBatch_.assign(s.h.elements().size(), 0);
      for (std::size_t g = g0_; g < g1_; ++g)
        if (NodeId r = s.links[s.groupStart[g]].receiver; !r.isCluster()) inBatch_[r.index()] = 1;
    }
    if (s.ext) indexElementLinks();
    // Each cluster's links, packed once (links are grouped by receiver); links that brought no light
    // are left out.
    samples_.assign(s.h.clusters().size(), {});
    // Every receiver's group is looked at in parallel: listing the clusters' groups first, serially,
    // read one link per receiver from memory on every sweep.
    if (!pullOnly_)
    tbb::parallel_for(g0_, g1_, [&](std::size_t g) {
      const NodeId r = s.links[s.groupStart[g]].receiver;
      if (!r.isCluster()) return;
      ClusterSamples& cs = samples_[r.index()];
      for (std::uint32_t k = s.groupStart[g]; k < s.groupStart[g + 1]; ++k) {
        const Link& l = s.links[k];
        if (l.E == glm::vec3(0.0f)) continue;
        cs.dx.push_back(l.dir.x), cs.dy.push_back(l.dir.y), cs.dz.push_back(l.dir.z);
        cs.er.push_back(l.E.x), cs.eg.push_back(l.E.y), cs.eb.push_back(l.E.z);
        const IncidentSample x = s.sampleOf(l);
        cs.dist.push_back(float(x.distance)), cs.radius.push_back(float(x.radius));
        if (carry_) cs.sender.push_back(l.sender.isCluster() ? kNone : l.sender.index());
      }
      cs.centre = s.h.center(r);
      while (cs.dx.size() % 4 != 0) {
        cs.dx.push_back(0.0f), cs.dy.push_back(0.0f), cs.dz.push_back(1.0f);
        cs.er.push_back(0.0f), cs.eg.push_back(0.0f), cs.eb.push_back(0.0f);
        cs.dist.push_back(0.0f), cs.radius.push_back(0.0f);
        if (carry_) cs.sender.push_back(kNone);
      }
    });
    if (prune_) markTouched();
    s.pushSkipped = 0;
  }

  void run() {
    SampleChain none;
    cluster(0, none);
  }

  /// Shooting: which root patches a pass changed (one of its elements received light, or it shot),
  /// counted along Hierarchy::patchOrder so that a cluster's share is a difference of two prefix
  /// counts. A cluster that received light changes every patch under it.
  void markTouched() {
    const std::vector<std::uint32_t>& pos = s_.patchPos;
    const std::size_t P = pos.size();
    std::vector<int> diff(P + 1, 0);
    auto mark = [&](std::uint32_t begin, std::uint32_t end) { ++diff[begin], --diff[end]; };
    // Pulling: everything the pass changed; a batch: its own receivers (shooters received nothing).
    for (std::size_t g = pullOnly_ ? 0 : g0_; g < (pullOnly_ ? groupCount() : g1_); ++g) {
      bool lit = false;
      for (std::uint32_t k = s_.groupStart[g]; k < s_.groupStart[g + 1] && !lit; ++k) lit = s_.links[k].E != glm::vec3(0.0f);
      if (!lit) continue;
      const NodeId r = s_.links[s_.groupStart[g]].receiver;
      if (r.isCluster()) {
        mark(s_.h.cluster(r.index()).patchBegin, s_.h.cluster(r.index()).patchEnd);
      } else {
        std::uint32_t at = pos[s_.h.element(r.index()).patch];
        mark(at, at + 1);
      }
    }
    if (!leavesOnly_)
      for (std::uint32_t p : s_.passShooters) mark(pos[p], pos[p] + 1);
    touchedBefore_.assign(P + 1, 0);
    int depth = 0;
    for (std::size_t i = 0; i < P; ++i) {
      depth += diff[i];
      touchedBefore_[i + 1] = touchedBefore_[i] + (depth > 0);
    }
  }
  std::size_t groupCount() const { return std::max<std::size_t>(s_.groupStart.size(), 1) - 1; }
  bool touched(std::uint32_t begin, std::uint32_t end) const { return touchedBefore_[end] > touchedBefore_[begin]; }

  /// The packed samples are freed in parallel: the clusters' small arrays, freed one by one on every
  /// sweep, were a third of what push/pull left serial on the Soda Shoppe.
  ~PushPull() {
    tbb::parallel_for(std::size_t(0), samples_.size(), [&](std::size_t c) { samples_[c] = ClusterSamples{}; });
  }

  /// Element receivers' link ranges, for the samples of subtrees the extension simulates.
  void indexElementLinks() {
    elemRange_.assign(s_.h.elements().size(), {0, 0});
    for (std::size_t g = g0_; g < g1_; ++g) {
      NodeId r = s_.links[s_.groupStart[g]].receiver;
      if (!r.isCluster()) elemRange_[r.index()] = {s_.groupStart[g], s_.groupStart[g + 1]};
    }
  }

 private:
  /// What an element subtree pulls up: area * B; area * what it sends (B, or U while shooting); and
  /// the first moment of what it sends about its area centroid, integral of B (y - g) dA per world
  /// axis (0 for a leaf: constant over it).
  struct Pulled {
    Rgb power{0.0}, sent{0.0};
    Rgb moment[3] = {Rgb(0.0), Rgb(0.0), Rgb(0.0)};
  };

  /// The least-squares linear fit of what an inner element's leaves send from its pulled first
  /// moment about its area centroid g: gradient = (second moment of area)^-1 first moment, along
  /// planeAxes.
  void fitGradient(std::uint32_t e, const Vec3& g, const Pulled& p) {
    const Element& el = s_.h.element(e);
    // Plain variables, not a structured binding: the lambda below captures them, which Debian's
    // clang 14 (the fuzz build) refuses for bindings.
    const std::pair<Vec3, Vec3> axes = planeAxes(el.poly, el.normal);
    const Vec3 t1 = axes.first, t2 = axes.second;
    // Second moment of area about g in (t1, t2), a fan of triangles: each adds A/12 (sum of p p^T + s s^T).
    double m11 = 0.0, m12 = 0.0, m22 = 0.0;
    auto at = [&](int i) { return glm::dvec2(glm::dot(el.poly.v[i] - g, t1), glm::dot(el.poly.v[i] - g, t2)); };
    for (int i = 1; i + 1 < el.poly.n; ++i) {
      const glm::dvec2 a = at(0), b = at(i), c = at(i + 1), sum = a + b + c;
      const double w = std::abs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)) / 24.0;  // area / 12
      m11 += w * (a.x * a.x + b.x * b.x + c.x * c.x + sum.x * sum.x);
      m12 += w * (a.x * a.y + b.x * b.y + c.x * c.y + sum.x * sum.y);
      m22 += w * (a.y * a.y + b.y * b.y + c.y * c.y + sum.y * sum.y);
    }
    const double det = m11 * m22 - m12 * m12;
    // Across the edge of a coplanar cover the leaves' radiosity steps from the open part's to none:
    // a line through that step would model the cover, not the light.
    if (!(det > 0.0) || s_.open[e] < 1.0f) {
      s_.gradU[e] = s_.gradV[e] = Rgb(0.0);
      return;
    }
    const Rgb b1 = p.moment[0] * t1.x + p.moment[1] * t1.y + p.moment[2] * t1.z;
    const Rgb b2 = p.moment[0] * t2.x + p.moment[1] * t2.y + p.moment[2] * t2.z;
    s_.gradU[e] = (m22 * b1 - m12 * b2) / det;
    s_.gradV[e] = (m11 * b2 - m12 * b1) / det;
  }

  /// Pushes irradiance down an element subtree and pulls radiosity up (Pulled). In a
  /// subtree the extension simulates, `samples` carries the Illumination Samples that reached the
  /// element from above (on its plane): the element adds its own links' samples, a leaf is
  /// reflected, an inner element pulled after its children (one traversal for all of them).
  Pulled element(std::uint32_t e, const Rgb& down, std::vector<IncidentSample>* samples) {
    // A wholly covered element has no open part for light to arrive at (coplanar.h): its radiosity
    // stays its emission, which its cover absorbs.
    Rgb total = s_.open[e] > 0.0f && !pullOnly_ ? down + (leavesOnly_ && !inBatch_[e] ? Rgb(0.0) : s_.Eg[e]) : Rgb(0.0);
    const Element& el = s_.h.element(e);
    // Shooting: the pass's irradiance adds to what arrived before.
    s_.Et[e] = shoot_ ? s_.Et[e] + total : total;
    std::size_t mark = samples ? samples->size() : 0;
    if (samples && carry_)
      for (std::uint32_t i = elemRange_[e].first; i < elemRange_[e].second; ++i)
        if (s_.links[i].E != glm::vec3(0.0f)) samples->push_back(s_.sampleOf(s_.links[i]));
    // An inner element offers what reached it to the extension, which may reflect once for every leaf
    // below what they all see alike (Extension::reflectShared); taken samples are not carried further
    // down, the rest are, re-aimed from each child's centre (hr::aimFrom). A shooting
    // batch re-offers every inner element on its way down, so a layer of an earlier batch is never
    // read by a later one.
    if (samples && carry_ && !el.leaf()) {
      samples->resize(s_.ext->reflectShared(NodeId{e}, *samples));
      mark = std::min(mark, samples->size());
    }
    Pulled result;
    if (el.leaf()) {
      if (shoot_) {
        // What the pass brought is reflected once: it joins the radiosity and waits to be shot.
        Rgb dB = s_.mat(e).diffuse * total;
        s_.B[e] += dB;
        s_.U[e] += dB;
        s_.Umin[e] = s_.Umax[e] = static_cast<float>(luminance(s_.U[e]));
      } else {
        s_.B[e] = s_.emitted(e) + s_.mat(e).diffuse * total;
      }
      s_.Bmin[e] = s_.Bmax[e] = static_cast<float>(luminance(s_.B[e]));
      // Called with no samples too: an ancestor may have taken them into its layer.
      if (samples && shoot_ && carry_) s_.ext->reflectShot(NodeId{e}, *samples);
      if (samples && !shoot_) s_.ext->reflect(NodeId{e}, *samples);
      // Radiosity is the open part's (SolverState::open): so is the power.
      result.power = s_.B[e] * s_.openArea(e);
      result.sent = shoot_ ? s_.U[e] * s_.openArea(e) : result.power;
    } else {
      Rgb sum(0.0), unshot(0.0);
      float lo = std::numeric_limits<float>::max(), hi = 0.0f;
      float ulo = std::numeric_limits<float>::max(), uhi = 0.0f;
      Pulled part[4];
      if (samples) {
        // A simulated subtree: reflection costs far more than a task, so the four children run in
        // parallel, each with its own copy of the samples so far (summed below in child order).
        tbb::parallel_for(0, 4, [&](int k) {
          s_.clkPushPull.sawThread();
          std::vector<IncidentSample> mine(*samples);
          const Vec3& to = s_.h.element(el.firstChild + std::uint32_t(k)).center;
          for (IncidentSample& x : mine) aimFrom(x, el.center, to);
          part[k] = element(el.firstChild + std::uint32_t(k), total, &mine);
        });
      } else {
        for (std::uint32_t k = 0; k < 4; ++k) part[k] = element(el.firstChild + k, total, nullptr);
      }
      if (leavesOnly_) {  // pulled once after the pass's last batch
        if (samples) samples->resize(mark);
        return result;
      }
      const Vec3 g = el.poly.areaCentroid();
      double openSum = 0.0;
      for (std::uint32_t k = 0; k < 4; ++k) {
        const std::uint32_t c = el.firstChild + k;
        sum += part[k].power;
        openSum += s_.openArea(c);
        const Vec3 d = s_.h.element(c).poly.areaCentroid() - g;
        result.sent += part[k].sent;
        for (int a = 0; a < 3; ++a) result.moment[a] += part[k].moment[a] + part[k].sent * d[a];
        lo = std::min(lo, s_.Bmin[c]);
        hi = std::max(hi, s_.Bmax[c]);
        if (shoot_) {
          unshot += s_.U[c] * s_.openArea(c);
          ulo = std::min(ulo, s_.Umin[c]);
          uhi = std::max(uhi, s_.Umax[c]);
        }
      }
      // The mean over the open part, where light arrives and leaves.
      s_.B[e] = openSum > 0.0 ? sum / openSum : s_.emitted(e);
      s_.Bmin[e] = lo, s_.Bmax[e] = hi;
      if (shoot_) s_.U[e] = openSum > 0.0 ? unshot / openSum : Rgb(0.0), s_.Umin[e] = ulo, s_.Umax[e] = uhi;
      if (samples) s_.ext->pull(NodeId{e}, s_.h.children(NodeId{e}));
      result.power = sum;
      fitGradient(e, g, result);
    }
    if (samples) samples->resize(mark);
    return result;
  }

  /// The chain's samples on a plane with normal n (E_perp max(0, n.w)), to start a simulated
  /// patch's sample list.
  void chainSamples(const SampleChain& chain, const Vec3& n, const Vec3& at,
                    std::vector<IncidentSample>& out) const {
    for (const SampleChain* c = &chain; c; c = c->parent) {
      if (!c->here) continue;
      const ClusterSamples& cs = *c->here;
      for (std::size_t i = 0; i < cs.dx.size(); ++i) {
        Vec3 w(cs.dx[i], cs.dy[i], cs.dz[i]);
        double cosine = glm::dot(n, w);
        Rgb e(cs.er[i], cs.eg[i], cs.eb[i]);
        if (!(cosine > 0.0 && maxComponent(e) > 0.0)) continue;
        IncidentSample s{w, e * cosine, double(cs.dist[i]), double(cs.radius[i])};
        if (const std::uint32_t k = cs.sender[i]; k != kNone) {
          const Element& from = s_.h.element(k);
          s.senderNormal = glm::vec3(from.normal), s.senderShape = from.shape;
        }
        aimFrom(s, cs.centre, at);
        out.push_back(s);
      }
    }
  }

  /// Irradiance on a plane with normal n from every sample in the chain: sum of E_perp max(0, n.w).
  static Rgb irradianceFrom(const SampleChain& chain, const Vec3& n) {
    const float nx = float(n.x), ny = float(n.y), nz = float(n.z);
    Rgb down(0.0);
    for (const SampleChain* c = &chain; c; c = c->parent) {
      if (!c->here) continue;
      const ClusterSamples& cs = *c->here;
      // Four lanes at a time (GCC/Clang vector extensions: the plain loop stayed scalar, a reduction
      // the compiler may not reorder); the arrays are padded with zero-light samples to a multiple of 4.
      using V4 = float __attribute__((vector_size(16)));
      V4 r{}, g{}, b{};
      for (std::size_t i = 0; i < cs.dx.size(); i += 4) {
        V4 x, y, z, er, eg, eb;
        std::memcpy(&x, &cs.dx[i], 16), std::memcpy(&y, &cs.dy[i], 16), std::memcpy(&z, &cs.dz[i], 16);
        std::memcpy(&er, &cs.er[i], 16), std::memcpy(&eg, &cs.eg[i], 16), std::memcpy(&eb, &cs.eb[i], 16);
        V4 w = nx * x + ny * y + nz * z;
        w = w > 0.0f ? w : V4{};
        r += er * w, g += eg * w, b += eb * w;
      }
      // Float within a cluster's links, double across levels.
      for (int j = 0; j < 4; ++j) down += Rgb(r[j], g[j], b[j]);
    }
    return down;
  }

  void cluster(std::uint32_t c, const SampleChain& up) {
    const Cluster& cl = s_.h.cluster(c);
    SampleChain here{&samples_[c], &up};
    // Shooting: a subtree no light reached and no shooter lies in is as the last pass left it (light
    // that reached a cluster touched every patch under it).
    if (prune_ && !touched(cl.patchBegin, cl.patchEnd)) {
      s_.pushSkipped.fetch_add(cl.patchEnd - cl.patchBegin, std::memory_order_relaxed);
      return;
    }
    auto child = [&](std::size_t k) {
      NodeId kid = cl.children[k];
      if (kid.isCluster()) {
        cluster(kid.index(), here);
        return;
      }
      const std::uint32_t at = prune_ ? s_.patchPos[s_.h.element(kid.index()).patch] : 0;
      if (prune_ && !touched(at, at + 1)) {
        s_.pushSkipped.fetch_add(1, std::memory_order_relaxed);
        return;
      }
      const Vec3& n = s_.h.element(kid.index()).normal;
      if (s_.ext && s_.owned[kid.index()]) {
        std::vector<IncidentSample> samples;
        if (carry_) chainSamples(here, n, s_.h.element(kid.index()).center, samples);
        element(kid.index(), irradianceFrom(here, n), &samples);
      } else {
        element(kid.index(), irradianceFrom(here, n), nullptr);
      }
    };
    // Tasks for large subtrees only (a task per small cluster cost more than its work), and for
    // subtrees holding simulated surfaces (their reflection costs far more than a task).
    if (cl.patchEnd - cl.patchBegin > kSerialPatches || (s_.ext && s_.clusterOwned[c])) {
      tbb::parallel_for(std::size_t(0), cl.children.size(), [&](std::size_t k) {
        s_.clkPushPull.sawThread();
        child(k);
      });
    } else {
      for (std::size_t k = 0; k < cl.children.size(); ++k) child(k);
    }
    if (leavesOnly_) return;  // pulled once after the pass's last batch
    if (s_.tableSlot[c] == kNone)
      exactPeak(c);
    else
      tablePull(c);
    if (s_.ext && s_.clusterOwned[c]) s_.ext->pull(NodeId{c | NodeId::kClusterBit}, cl.children);
  }

  /// A large cluster's table: its child clusters' tables (or, for those evaluated exactly, their
  /// patches' cosine lobes) plus its own patches' lobes.
  void tablePull(std::uint32_t c) {
    const Cluster& cl = s_.h.cluster(c);
    float* t = s_.clusterTable(c);
    constexpr int N = OctaMap::kBins * 3;
    std::fill(t, t + N, 0.0f);
    for (NodeId kid : cl.children) {
      if (kid.isCluster() && s_.tableSlot[kid.index()] != kNone) {
        const float* tk = s_.clusterTable(kid.index());
        for (int i = 0; i < N; ++i) t[i] += tk[i];
        continue;
      }
      if (kid.isCluster()) {
        const Cluster& kc = s_.h.cluster(kid.index());
        for (std::uint32_t i = kc.patchBegin; i < kc.patchEnd; ++i) addPatch(t, s_.h.patchOrder()[i]);
      } else {
        addPatch(t, kid.index());
      }
    }
    // The cosine-free bound of the cluster's sending side, read by the oracle for every link.
    double m = 0.0;
    for (int i = 0; i < OctaMap::kBins; ++i)
      m = std::max(m, luminance(Rgb(t[i], t[OctaMap::kBins + i], t[2 * OctaMap::kBins + i])));
    s_.peak[c] = m;
  }
  void addPatch(float* t, std::uint32_t p) {
    const Patch& pt = s_.h.patches()[p];
    // (The root element of patch p has index p.)
    addCosineLobe(t, pt.normal, s_.clusterSource()[p] * (s_.openArea(p) / kPi));
  }

  /// A small cluster's peak intensity, estimated in O(patches): its exact intensity toward the
  /// power-weighted mean normal (where a sum of cosine lobes of similar normals peaks), or its
  /// brightest patch's own peak if that is more.
  void exactPeak(std::uint32_t c) {
    const Cluster& cl = s_.h.cluster(c);
    Vec3 mean(0.0);
    double single = 0.0;
    for (std::uint32_t i = cl.patchBegin; i < cl.patchEnd; ++i) {
      const Patch& p = s_.h.patches()[s_.h.patchOrder()[i]];
      double w = luminance(s_.clusterSource()[s_.h.patchOrder()[i]]) * s_.openArea(s_.h.patchOrder()[i]);
      mean += p.normal * w;
      single = std::max(single, w / kPi);
    }
    double m = glm::length(mean) > 0.0 ? luminance(s_.clusterIntensity(c, glm::normalize(mean))) : 0.0;
    s_.peak[c] = std::max(m, single);
  }

  SolverState& s_;
  const bool shoot_;  // add the pass's light (shooting) instead of replacing (gathering)
  const bool prune_;  // shooting: visit only the subtrees the pass changed
  const bool leavesOnly_;  // shooting in batches: add one batch's light to the leaves, pull nothing
  const bool pullOnly_;    // shooting in batches: pull what the pass changed, add nothing
  const bool carry_;  // carry samples down to simulated leaves (not for an extension that reflects in gather)
  const std::size_t g0_, g1_;  // the receiver groups whose light this push adds
  std::vector<std::uint8_t> inBatch_;  // leavesOnly_: per element, whether its own group is in [g0_, g1_)
  std::vector<ClusterSamples> samples_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> elemRange_;  // element receivers' links
  std::vector<std::uint32_t> touchedBefore_;   // shooting: changed patches among patchOrder[0..i)
};

}  // namespace

void pushPull(SolverState& s, PushMode mode, std::size_t groupBegin, std::size_t groupEnd) {
  PhaseTimer t(s.clkPushPull);
  PushPull(s, mode, groupBegin, groupEnd).run();
}

}  // namespace hr::detail
