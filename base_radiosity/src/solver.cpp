// Diffuse hierarchical radiosity with clustering (in the manner of Smits et al. 1994 and Sillion
// 1995). One iteration = refine links (evaluate new ones in parallel, decide serially so the result
// does not depend on the thread count) -> gather along links -> push/pull. Clusters send and receive
// light as radiant intensity / normal irradiance; elements as radiosity / irradiance.
#include <hr/octamap.h>
#include <hr/kernel.h>
#include <hr/rng.h>
#include <hr/solver.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace hr {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kEscapeBudget = 1 << 20;  // rays shared among leaves by power, for the energy check
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct Link {
  NodeId sender, receiver;
  float coef = 0.0f;    // element receiver: irradiance per unit sender quantity; cluster: E_perp per unit
  float spread = 0.0f;  // relative uncertainty of coef from its samples
  float geom = 0.0f;    // (r_s + r_r) / d for links with a cluster end, 0 otherwise
  float bound = 0.0f;   // coef with cosines replaced by 1: the oracle's upper bound
  glm::vec3 dir{0.0f};  // receiver -> sender, unit
  glm::vec3 E{0.0f};    // last transported irradiance (element) or normal irradiance (cluster), W/m^2
  float at[5] = {};     // element-element links: unoccluded point form factors at the receiver's
                        // corners (pulled inward; a triangle repeats its centre) and centre
  float wkid[4] = {};   // point form factors from the centres of the sender's four quadtree children
  bool evaluated = false;
};

struct Sample {
  Vec3 dir;
  Rgb e;  // normal irradiance, W/m^2
};

}  // namespace

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
  const Scene& scene;
  Hierarchy& h;
  const Visibility& vis;
  SolverOptions opt;
  Extension* ext;
  Progress* progress;
  Progress silent{true};

  std::vector<Rgb> B, Bprev, Eg, Et;  // per element: radiosity, previous, gathered, total irradiance
  std::vector<float> table;           // per cluster: OctaMap::kBins RGB intensities, W/sr
  std::vector<double> peak;           // per cluster: largest luminance in its table, W/sr
  std::vector<std::uint8_t> owned;    // per element / cluster: extension owns it (subtree has handled material)
  std::vector<std::uint8_t> clusterOwned;
  std::vector<Link> links;
  std::vector<std::uint32_t> groupStart;  // receivers' link ranges after sorting
  double emittedPower = 0.0;             // luminance, W
  double minArea = 0.0;
  std::uint64_t rays = 0;

  Impl(const Scene& s, Hierarchy& hi, const Visibility& v, const SolverOptions& o, Extension* e, Progress* p)
      : scene(s), h(hi), vis(v), opt(o), ext(e), progress(p ? p : &silent) {}

  // ---- HostView --------------------------------------------------------------------------
  NodeId root() const override { return h.root(); }
  NodeInfo info(NodeId n) const override {
    NodeInfo i;
    if (n.isCluster()) {
      const Cluster& c = h.cluster(n.index());
      i.center = c.center;
      i.area = c.area;
      i.bounds = c.bounds;
      return i;
    }
    const Element& e = h.element(n.index());
    i.center = e.center;
    i.normal = e.normal;
    i.area = e.area;
    i.planar = true;
    i.leaf = e.leaf();
    i.material = h.patches()[e.patch].material;
    i.object = h.patches()[e.patch].object;
    for (int k = 0; k < e.poly.n; ++k) i.bounds.grow(e.poly.v[k]);
    return i;
  }
  std::span<const NodeId> children(NodeId n) const override { return h.children(n); }
  std::size_t elementCount() const override { return h.elements().size(); }
  std::size_t clusterCount() const override { return h.clusters().size(); }
  std::size_t materialCount() const override { return scene.materials.size(); }
  MaterialInfo material(std::uint32_t id) const override {
    const Material& m = scene.materials[id];
    return {m.diffuse, m.specular, m.exponent, m.emission};
  }

  // ---- per-node quantities ------------------------------------------------------------------
  const Material& mat(std::uint32_t e) const { return scene.materials[h.patches()[h.element(e).patch].material]; }
  Rgb emitted(std::uint32_t e) const { return kPi * mat(e).emission; }

  void growArrays() {
    std::size_t n = h.elements().size();
    std::size_t old = B.size();
    B.resize(n);
    Bprev.resize(n);
    Eg.resize(n, Rgb(0.0));
    Et.resize(n, Rgb(0.0));
    owned.resize(n, 0);
    for (std::size_t i = old; i < n; ++i) {
      const Element& e = h.element(static_cast<std::uint32_t>(i));
      // A new child starts with its parent's radiosity so that refinement does not perturb B.
      B[i] = e.parent == kNone ? emitted(static_cast<std::uint32_t>(i)) : B[e.parent];
      Bprev[i] = B[i];
      Et[i] = e.parent == kNone ? Rgb(0.0) : Et[e.parent];
      owned[i] = e.parent == kNone ? 0 : owned[e.parent];
    }
  }

  /// The sender's quantity for a link: radiosity for elements (W/m^2), intensity toward the
  /// receiver for clusters (W/sr).
  Rgb senderValue(const Link& l) const {
    Vec3 toRecv = -Vec3(l.dir);
    Rgb v = diffuseSenderValue(l, toRecv);
    if (ext && isOwned(l.sender)) {
      // Additive: the extension's directional share joins the host's Lambertian light.
      Rgb I = ext->intensity(l.sender, toRecv);
      if (l.sender.isCluster()) return v + I;
      const Element& e = h.element(l.sender.index());
      double c = glm::dot(e.normal, toRecv);
      if (c > 1e-6) v += kPi * I / (e.area * c);
    }
    return v;
  }
  bool isOwned(NodeId n) const { return n.isCluster() ? clusterOwned[n.index()] != 0 : owned[n.index()] != 0; }
  Rgb diffuseSenderValue(const Link& l, const Vec3& toRecv) const {
    if (l.sender.isCluster()) return OctaMap::lookup(&table[std::size_t(l.sender.index()) * OctaMap::kBins * 3], toRecv);
    const Element& e = h.element(l.sender.index());
    if (!e.leaf()) {
      double ws = l.wkid[0] + l.wkid[1] + l.wkid[2] + l.wkid[3];
      if (ws > 0.0) {
        Rgb b(0.0);
        for (int k = 0; k < 4; ++k) b += double(l.wkid[k]) * B[e.firstChild + k];
        return b / ws;
      }
    }
    return B[l.sender.index()];
  }

  // ---- sampling points on nodes ----------------------------------------------------------------
  /// A point on a node's surface, lifted off it along its normal by the visibility epsilon: rays
  /// from points within ~1e-4 of a neighbouring face (a cube's edge) otherwise graze that face in
  /// single precision and report a hit, which made every link of such a point look blocked.
  Vec3 pointOn(NodeId n, double u, double w, Rng& rng, Vec3& normal) const {
    if (!n.isCluster()) {
      const Element& e = h.element(n.index());
      normal = e.normal;
      return lifted(e, e.poly.sample(u, w));
    }
    const Cluster& c = h.cluster(n.index());
    const auto& pre = h.patchAreaPrefix();
    double a = pre[c.patchBegin] + u * (pre[c.patchEnd] - pre[c.patchBegin]);
    auto it = std::upper_bound(pre.begin() + c.patchBegin, pre.begin() + c.patchEnd + 1, a);
    std::size_t idx = std::clamp<std::size_t>(std::size_t(it - pre.begin()) - 1, c.patchBegin, c.patchEnd - 1);
    const Patch& p = h.patches()[h.patchOrder()[idx]];
    normal = p.normal;
    return p.poly.sample(rng.uniform(), w) + p.normal * vis.epsilon();
  }
  Vec3 lifted(const Element& e, const Vec3& x) const { return x + e.normal * vis.epsilon(); }

  /// cos cos / r^2 between two surface points (up to 1/pi), 0 unless they face each other: the
  /// weight of a shadow ray in a link's visible fraction.
  static double pointKernel(const Vec3& x, const Vec3& nx, const Vec3& y, const Vec3& ny) {
    Vec3 xy = y - x;
    double d2 = glm::dot(xy, xy), cx = glm::dot(nx, xy), cy = -glm::dot(ny, xy);
    return cx > 0.0 && cy > 0.0 && d2 > 0.0 ? cx * cy / (d2 * d2) : 0.0;
  }

  /// Computes coef, spread, bound and direction of a new link, tracing its shadow rays together.
  int evaluate(Link& l) const {
    const int K = opt.raysPerLink;
    Vec3 from[256], to[256];
    bool blocked[256];
    double val[256];
    for (int k = 0; k < K; ++k) from[k] = to[k] = Vec3(0.0);  // (quiets GCC's maybe-uninitialized)
    Rng rr(opt.seed, l.receiver.value, 0x5EC);  // receiver points: the same for all of its links
    Rng rs(opt.seed, l.sender.value, l.receiver.value);
    Vec3 centreS = h.center(l.sender), centreR = h.center(l.receiver);
    Vec3 d = centreS - centreR;
    double dist = glm::length(d);
    l.dir = glm::vec3(dist > 0.0 ? d / dist : Vec3(0, 0, 1));
    l.evaluated = true;
    bool ee = !l.sender.isCluster() && !l.receiver.isCluster();
    int n = 0;
    if (ee) {
      const Element& s = h.element(l.sender.index());
      const Element& r = h.element(l.receiver.index());
      if (s.patch == r.patch) return 0;
      // The oracle's variation comes from fixed points (corners pulled 1e-3 inward, and the centre),
      // not from the points that set the coefficient: deciding on the same random samples that set
      // the value would keep preferentially the links whose samples happen to agree, a bias.
      Vec3 c = r.center;
      double lo = pointPolygonFormFactor(c, r.normal, s.poly, s.normal), hi = lo;
      l.at[4] = l.at[3] = static_cast<float>(lo);
      for (int k = 0; k < r.poly.n; ++k) {
        double f = pointPolygonFormFactor(r.poly.v[k] + 1e-3 * (c - r.poly.v[k]), r.normal, s.poly, s.normal);
        l.at[k] = static_cast<float>(f);
        lo = std::min(lo, f);
        hi = std::max(hi, f);
      }
      // The coefficient: the unoccluded form factor averaged over the receiver by Gauss-Legendre
      // quadrature (deterministic: a jittered 4x4 grid left 5 % errors on links across a shared
      // edge, where the point form factor climbs steeply towards 1/2), times the visible fraction
      // from K rays weighted by form factor.
      double fmean = meanFormFactor(r.poly, r.normal, s.poly, s.normal, hi - lo > 0.5 * hi ? 6 : 4);
      // Sender points: ray k lands in the sender's quadtree child k % 4 (stratified inside it), so
      // that the visible kernel weight of each child is known (see senderValue).
      const auto kidsPoly = s.poly.subdivide();
      const int perKid = (K + 3) / 4;
      for (int k = 0; k < K; ++k) {
        Vec3 x = r.poly.sample((k + rr.uniform()) / K, rr.uniform());
        const Polygon& kid = kidsPoly[k % 4];
        Vec3 y = kid.sample((k / 4 + rs.uniform()) / perKid, rs.uniform());
        val[k] = pointKernel(x, r.normal, y, s.normal) * (4.0 * kid.area() / s.area);
        if (val[k] > 0.0) {
          from[n] = lifted(r, x);
          to[n] = lifted(s, y);
          ++n;
        }
      }
      vis.occluded(from, to, n, blocked);
      // The visible fraction weights each ray by the point-to-point kernel cos cos / r^2: weighting
      // by area alone took an occluder that hides the far half of a sender for hiding half of the
      // transfer, and a thin light panel under a ceiling cost the room 1 % of its power.
      double wsum = 0.0, vsum = 0.0;
      int nvis = 0;
      double kidw[4] = {0, 0, 0, 0};
      for (int k = 0, j = 0; k < K; ++k) {
        if (val[k] <= 0.0) continue;
        bool b = blocked[j++];
        wsum += val[k];
        vsum += b ? 0.0 : val[k];
        kidw[k % 4] += b ? 0.0 : val[k];
        nvis += b ? 0 : 1;
      }
      for (int k = 0; k < 4; ++k) l.wkid[k] = static_cast<float>(wsum > 0.0 ? kidw[k] / wsum : 0.0);
      double V = wsum > 0.0 ? vsum / wsum : 1.0;
      l.coef = static_cast<float>(fmean * V);
      // The bound is the unoccluded transfer: a link whose few rays were all blocked may still be
      // partly visible, so it must be refined (or found small) rather than dropped.
      l.bound = static_cast<float>(fmean);
      double vspread = nvis < n ? 1.0 : 0.0;  // any blocked ray: visibility is uncertain
      l.spread = fmean > 0.0 ? static_cast<float>((hi - lo) / std::max(fmean, 1e-300) + vspread) : 0.0f;
      l.geom = 0.0f;
      return n;
    }
    // A cluster at one end: point kernel between centres, visible fraction from K rays between
    // area-sampled surface points. Only pairs whose surfaces face each other count, each weighted by
    // the point kernel: a box's faces turned away from the sender see it through the box itself, and
    // counting them as blocked starved the faces that do see it (a room lost 2 % of its power).
    Vec3 nf[256], nt[256];
    for (int k = 0; k < K; ++k) {
      from[k] = pointOn(l.receiver, (k + rr.uniform()) / K, rr.uniform(), rr, nf[k]);
      to[k] = pointOn(l.sender, (k + rs.uniform()) / K, rs.uniform(), rs, nt[k]);
    }
    n = K;
    vis.occluded(from, to, n, blocked);
    int visible = 0, facing = 0;
    double wsum = 0.0, vsum = 0.0;
    for (int k = 0; k < K; ++k) {
      double wk = pointKernel(from[k], nf[k], to[k], nt[k]);
      if (wk <= 0.0) continue;
      ++facing;
      wsum += wk;
      vsum += blocked[k] ? 0.0 : wk;
      visible += blocked[k] ? 0 : 1;
    }
    double V = wsum > 0.0 ? vsum / wsum : 1.0;
    // The plain 1/d^2 between centres. A cluster link can always be split, and the oracle's geometric
    // term (r_s + r_r) / d splits close ones, so the kernel need not be bounded here; bounding it by
    // d^2 + r_s^2 + r_r^2 underestimated every kept link and cost a room 2 % of its power.
    double rs2 = h.radius(l.sender), rr2 = h.radius(l.receiver);
    double denom = std::max(dist * dist, 1e-12 * (rs2 + rr2) * (rs2 + rr2));
    Vec3 w = Vec3(l.dir);
    double cosR = l.receiver.isCluster() ? 1.0 : std::max(0.0, glm::dot(h.element(l.receiver.index()).normal, w));
    double g = 1.0 / denom;  // unoccluded; V applies to coef only
    if (l.sender.isCluster()) {
      l.coef = static_cast<float>(V * g * cosR);
      l.bound = static_cast<float>(g);
    } else {
      const Element& s = h.element(l.sender.index());
      double cosS = std::max(0.0, -glm::dot(s.normal, w));
      l.coef = static_cast<float>(V * g * cosR * cosS * s.area / kPi);
      l.bound = static_cast<float>(g * s.area / kPi);
    }
    l.spread = visible < facing || facing == 0 ? 1.0f : 0.0f;
    l.geom = static_cast<float>(dist > 0.0 ? (rs2 + rr2) / dist : 1e30);
    return n;
  }
  bool canSplit(NodeId n) const {
    if (n.isCluster()) return !h.cluster(n.index()).children.empty();
    const Element& e = h.element(n.index());
    return e.level < static_cast<std::uint32_t>(opt.maxLevel) && e.area * 0.25 >= minArea;
  }

  /// The oracle: estimated error of the power the link brings to its receiver, W (luminance): the
  /// receiver's area times the sender's value times the transfer bound times its relative spread.
  double linkError(const Link& l) const {
    double S = luminance(senderValue(l));
    if (l.sender.isCluster()) S = std::max(S, peak[l.sender.index()]);
    // A cluster catches light with its projected area, on average a quarter of its surface area
    // (Cauchy's formula for convex bodies; an estimate for the rest).
    double area = h.area(l.receiver) * (l.receiver.isCluster() ? 0.25 : 1.0);
    double uncertainty = std::max<double>(l.spread, l.geom);
    return area * S * l.bound * uncertainty;
  }

  void split(const Link& l, std::vector<Link>& out) {
    auto make = [&](NodeId s, NodeId r) {
      Link c;
      c.sender = s;
      c.receiver = r;
      out.push_back(c);
    };
    if (l.sender == l.receiver) {
      // Self-link of a cluster: every ordered pair of children, and the children's self-links.
      auto kids = h.children(l.sender);
      std::vector<NodeId> ks(kids.begin(), kids.end());
      for (NodeId a : ks)
        for (NodeId b : ks)
          if (!(a == b) || a.isCluster()) make(a, b);
      return;
    }
    bool s = canSplit(l.sender), r = canSplit(l.receiver);
    bool splitSender = s && (!r || h.radius(l.sender) > h.radius(l.receiver));
    NodeId n = splitSender ? l.sender : l.receiver;
    if (!n.isCluster()) {
      h.subdivide(n.index());
      growArrays();
    }
    auto kids = h.children(n);
    std::vector<NodeId> ks(kids.begin(), kids.end());
    for (NodeId k : ks) splitSender ? make(k, l.receiver) : make(l.sender, k);
  }

  bool refinable(const Link& l) const {
    if (l.sender == l.receiver) return true;
    return canSplit(l.sender) || canSplit(l.receiver);
  }

  /// The receiver pass. The per-link oracle bounds each link's error alone, but a receiver near an
  /// edge or corner holds hundreds of links whose small errors share one sign (every one of them
  /// averages the form factor over a receiver that straddles a steep gradient), and a leaf's
  /// form-factor sum came out 5 % off in a closed cube. So for every element receiver that can still
  /// split, the irradiance its element links deliver is also evaluated at its corners and centre; if
  /// area * (max - min) exceeds the threshold, the receiver is subdivided and all its links move down
  /// to the children (where the per-link oracle sees them again). Returns the receivers split.
  std::size_t receiverPass(std::vector<Link>& kept, std::vector<Link>& out, double threshold) {
    std::stable_sort(kept.begin(), kept.end(),
                     [](const Link& a, const Link& b) { return a.receiver.value < b.receiver.value; });
    std::vector<std::uint32_t> start;
    for (std::uint32_t i = 0; i < kept.size(); ++i)
      if (i == 0 || !(kept[i].receiver == kept[i - 1].receiver)) start.push_back(i);
    start.push_back(static_cast<std::uint32_t>(kept.size()));
    std::vector<std::uint8_t> splitIt(start.size() - 1, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, start.size() - 1, 16), [&](const auto& r) {
      for (std::size_t g = r.begin(); g != r.end(); ++g) {
        NodeId recv = kept[start[g]].receiver;
        if (recv.isCluster() || !canSplit(recv)) continue;
        double e[5] = {0, 0, 0, 0, 0};
        for (std::uint32_t i = start[g]; i < start[g + 1]; ++i) {
          const Link& l = kept[i];
          if (l.sender.isCluster() || l.bound <= 0.0f) continue;
          double S = luminance(senderValue(l)) * (double(l.coef) / l.bound);  // times the visible fraction
          for (int k = 0; k < 5; ++k) e[k] += S * l.at[k];
        }
        auto [lo, hi] = std::minmax_element(e, e + 5);
        splitIt[g] = h.area(recv) * (*hi - *lo) > threshold ? 1 : 0;
      }
    });
    std::vector<Link> stay;
    std::size_t count = 0;
    for (std::size_t g = 0; g + 1 < start.size(); ++g) {
      if (!splitIt[g]) {
        stay.insert(stay.end(), kept.begin() + start[g], kept.begin() + start[g + 1]);
        continue;
      }
      NodeId recv = kept[start[g]].receiver;
      h.subdivide(recv.index());
      growArrays();
      ++count;
      auto kids = h.children(recv);
      std::vector<NodeId> ks(kids.begin(), kids.end());
      for (std::uint32_t i = start[g]; i < start[g + 1]; ++i)
        for (NodeId k : ks) {
          Link c;
          c.sender = kept[i].sender;
          c.receiver = k;
          out.push_back(c);
        }
    }
    kept = std::move(stay);
    return count;
  }

  /// One refinement pass over every link; returns the number of links split.
  std::size_t refine(SolveStats& st) {
    std::vector<Link> pending = std::move(links), kept;
    links.clear();
    std::size_t split_count = 0;
    const double threshold = opt.eps * emittedPower;
    while (!pending.empty()) {
      auto tv = Clock::now();
      std::vector<int> counts(pending.size(), 0);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pending.size(), 64), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i)
          if (!pending[i].evaluated) counts[i] = evaluate(pending[i]);
      });
      for (int c : counts) rays += c;
      st.tVisibility += since(tv);
      auto tr = Clock::now();
      std::vector<Link> next;
      for (const Link& l : pending) {
        bool self = l.sender == l.receiver;
        if (self || (refinable(l) && linkError(l) > threshold)) {
          if (self && (!l.sender.isCluster())) continue;  // a planar element cannot see itself
          split(l, next);
          ++split_count;
        } else if (l.bound > 0.0f) {
          // Kept even when every ray was blocked: the link may be partly visible, and its sender may
          // brighten later; dropping such links for good lost 1-2 % of a room's power.
          kept.push_back(l);
        }
      }
      pending = std::move(next);
      if (pending.empty()) split_count += receiverPass(kept, pending, threshold);
      st.tRefine += since(tr);
    }
    links = std::move(kept);
    std::stable_sort(links.begin(), links.end(),
                     [](const Link& a, const Link& b) { return a.receiver.value < b.receiver.value; });
    groupStart.clear();
    for (std::uint32_t i = 0; i < links.size(); ++i)
      if (i == 0 || !(links[i].receiver == links[i - 1].receiver)) groupStart.push_back(i);
    groupStart.push_back(static_cast<std::uint32_t>(links.size()));
    return split_count;
  }

  void gather() {
    std::fill(Eg.begin(), Eg.end(), Rgb(0.0));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, groupStart.size() - 1, 16), [&](const auto& r) {
      for (std::size_t g = r.begin(); g != r.end(); ++g) {
        Rgb sum(0.0);
        NodeId recv = links[groupStart[g]].receiver;
        for (std::uint32_t i = groupStart[g]; i < groupStart[g + 1]; ++i) {
          Link& l = links[i];
          Rgb e = double(l.coef) * senderValue(l);
          l.E = glm::vec3(e);
          sum += e;
        }
        if (!recv.isCluster()) Eg[recv.index()] = sum;
      }
    });
  }

  // ---- push / pull ----------------------------------------------------------------------------
  std::pair<std::uint32_t, std::uint32_t> linkRange(NodeId n) const {
    if (groupStart.size() < 2) return {0, 0};
    auto it = std::lower_bound(groupStart.begin(), groupStart.end() - 1, n.value,
                               [&](std::uint32_t gi, std::uint32_t v) { return links[gi].receiver.value < v; });
    if (it == groupStart.end() - 1 || !(links[*it].receiver == n)) return {0, 0};
    return {*it, *(it + 1)};
  }

  /// Pushes irradiance down an element subtree and pulls radiosity up; returns area * B.
  Rgb pushElement(std::uint32_t e, const Rgb& down) {
    Rgb total = down + Eg[e];
    const Element& el = h.element(e);
    if (el.leaf()) {
      Et[e] = total;
      B[e] = emitted(e) + mat(e).diffuse * total;
      return B[e] * el.area;
    }
    Et[e] = total;
    Rgb sum(0.0);
    for (std::uint32_t k = 0; k < 4; ++k) sum += pushElement(el.firstChild + k, total);
    B[e] = sum / el.area;
    return sum;
  }

  void pushCluster(std::uint32_t c, std::vector<Sample>& samples) {
    std::size_t mark = samples.size();
    auto [b, e] = linkRange(NodeId{c | NodeId::kClusterBit});
    for (std::uint32_t i = b; i < e; ++i)
      if (links[i].E != glm::vec3(0.0f)) samples.push_back({Vec3(links[i].dir), Rgb(links[i].E)});
    float* t = &table[std::size_t(c) * OctaMap::kBins * 3];
    std::fill(t, t + OctaMap::kBins * 3, 0.0f);
    for (NodeId k : h.cluster(c).children) {
      if (k.isCluster()) {
        pushCluster(k.index(), samples);
        const float* tk = &table[std::size_t(k.index()) * OctaMap::kBins * 3];
        for (int i = 0; i < OctaMap::kBins * 3; ++i) t[i] += tk[i];
      } else {
        const Element& el = h.element(k.index());
        Rgb down(0.0);
        for (const Sample& s : samples) down += s.e * std::max(0.0, glm::dot(el.normal, s.dir));
        pushElement(k.index(), down);
        Rgb rad = B[k.index()] * (el.area / kPi);
        for (int i = 0; i < OctaMap::kBins; ++i) {
          double cs = glm::dot(el.normal, OctaMap::binDirection(i));
          if (cs <= 0.0) continue;
          for (int ch = 0; ch < 3; ++ch) t[3 * i + ch] += static_cast<float>(rad[ch] * cs);
        }
      }
    }
    // The cosine-free bound of the cluster's sending side, read by the oracle for every link.
    double m = 0.0;
    for (int i = 0; i < OctaMap::kBins; ++i) m = std::max(m, luminance(Rgb(t[3 * i], t[3 * i + 1], t[3 * i + 2])));
    peak[c] = m;
    samples.resize(mark);
  }

  void pushPull() {
    std::vector<Sample> samples;
    pushCluster(0, samples);
  }

  void markOwned() {
    clusterOwned.assign(h.clusters().size(), 0);
    if (!ext) return;
    for (std::uint32_t p = 0; p < h.patches().size(); ++p)
      owned[p] = ext->simulates(material(h.patches()[p].material)) ? 1 : 0;
    // Clusters are built with children after parents: a reverse sweep sees children first.
    for (std::size_t c = h.clusters().size(); c-- > 0;)
      for (NodeId k : h.cluster(static_cast<std::uint32_t>(c)).children)
        clusterOwned[c] |= k.isCluster() ? clusterOwned[k.index()] : owned[k.index()];
  }

  // ---- energy ---------------------------------------------------------------------------------
  /// Absorbed and escaped power, measured independently of the links. Fronts absorb A (1 - rho) E.
  /// Surfaces are one-sided: light that reaches a back face (the top of a ceiling light panel, the
  /// outside of a box seen through a gap) is absorbed there, a black back, and is found with the
  /// escaped power by cosine-distributed rays from every leaf. Without it a thin light under a
  /// ceiling lost 1-2 % of the emitted power from the balance.
  void energy(SolveStats& st) {
    const auto& els = h.elements();
    std::vector<Rgb> esc(els.size(), Rgb(0.0)), back(els.size(), Rgb(0.0)), abs(els.size(), Rgb(0.0));
    const auto& patches = h.patches();
    // Rays per leaf: a floor of escapeRays, plus a share of a fixed budget in proportion to the
    // leaf's power. An emitter's few large leaves carry much of the light, and 64 rays each left a
    // +-1.5 % noise on a room's escaped power.
    double sent = 0.0;
    for (std::size_t i = 0; i < els.size(); ++i)
      if (els[i].leaf()) sent += luminance(B[i]) * els[i].area;
    std::atomic<std::uint64_t> traced{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, els.size(), 64), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        const Element& e = els[i];
        if (!e.leaf()) continue;
        abs[i] = e.area * (Rgb(1.0) - mat(static_cast<std::uint32_t>(i)).diffuse) * Et[i];
        if (maxComponent(B[i]) <= 0.0) continue;
        const double share = sent > 0.0 ? luminance(B[i]) * e.area / sent : 0.0;
        const int M = opt.escapeRays + static_cast<int>(std::min(1e6, std::ceil(share * kEscapeBudget)));
        traced += std::uint64_t(M);
        Rng rng(opt.seed ^ 0xE5CA9Eull, i);
        Vec3 t = std::abs(e.normal.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
        Vec3 u = glm::normalize(glm::cross(t, e.normal)), v = glm::cross(e.normal, u);
        int miss = 0, backHits = 0;
        const int side = std::max(1, static_cast<int>(std::lround(std::sqrt(double(M)))));
        for (int k = 0; k < M; ++k) {
          // Uniform over the leaf, stratified over the cosine-weighted hemisphere (2D grid).
          Vec3 o = e.poly.sample(rng.uniform(), rng.uniform());
          int sx = k % side, sy = (k / side) % side;
          double a = 2.0 * kPi * (sx + rng.uniform()) / side, s = std::sqrt((sy + rng.uniform()) / side);
          Vec3 d = s * std::cos(a) * u + s * std::sin(a) * v + std::sqrt(std::max(0.0, 1.0 - s * s)) * e.normal;
          SurfaceHit hit = vis.intersect(lifted(e, o), d);
          if (!hit.hit)
            ++miss;
          else if (glm::dot(patches[hit.patch].normal, d) > 0.0)
            ++backHits;
        }
        esc[i] = B[i] * e.area * (double(miss) / M);
        back[i] = B[i] * e.area * (double(backHits) / M);
      }
    });
    for (std::size_t i = 0; i < els.size(); ++i) {
      st.escapedW += esc[i];
      st.backAbsorbedW += back[i];
      st.absorbedW += abs[i] + back[i];
    }
    rays += traced;
  }

  SolveStats solve() {
    SolveStats st;
    auto t0 = Clock::now();
    st.initialPatches = h.patches().size();
    double totalArea = 0.0;
    for (const Patch& p : h.patches()) totalArea += p.area;
    minArea = opt.minArea > 0.0 ? opt.minArea : totalArea * 1e-6;
    growArrays();
    markOwned();
    for (const Patch& p : h.patches()) st.emittedW += kPi * scene.materials[p.material].emission * p.area;
    emittedPower = luminance(st.emittedW);
    table.assign(h.clusters().size() * OctaMap::kBins * 3, 0.0f);
    peak.assign(h.clusters().size(), 0.0);
    {
      std::vector<Sample> none;
      pushCluster(0, none);  // initial cluster intensities from the emitters
    }
    links.clear();
    links.push_back(Link{h.root(), h.root()});
    double rhoMean = 0.0;
    for (const Patch& p : h.patches()) rhoMean += luminance(scene.materials[p.material].diffuse) * p.area;
    rhoMean /= std::max(totalArea, 1e-300);
    for (int it = 1; it <= opt.maxIterations; ++it) {
      auto ti = Clock::now();
      progress->phase("iteration " + std::to_string(it) + ": refine");
      std::size_t refined = refine(st);
      if (ext) ext->attach(*this);
      progress->phase("iteration " + std::to_string(it) + ": gather");
      auto tg = Clock::now();
      for (std::size_t i = 0; i < B.size(); ++i) Bprev[i] = B[i];
      gather();
      st.tGather += since(tg);
      auto tp = Clock::now();
      pushPull();
      st.tPushPull += since(tp);
      double res = 0.0;
      for (std::uint32_t p = 0; p < h.patches().size(); ++p) res += h.patches()[p].area * std::abs(luminance(B[p] - Bprev[p]));
      IterationStat is;
      is.iteration = it;
      is.residualW = res;
      is.unconvergedW = res * rhoMean / std::max(1e-6, 1.0 - rhoMean);
      is.links = links.size();
      is.elements = h.elements().size();
      is.refined = refined;
      is.seconds = since(ti);
      st.history.push_back(is);
      st.iterations = it;
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "iteration %d: residual %.3e W (%.2e of emitted), unconverged ~%.3e W, links %zu, elements %zu, split %zu",
                    it, res, res / std::max(emittedPower, 1e-300), is.unconvergedW, links.size(), h.elements().size(), refined);
      progress->note(buf);
      // Convergence as a percentage: how far the residual has fallen, on a log scale, from the
      // first iteration's toward the tolerance.
      double first = st.history.front().residualW, target = opt.tolerance * emittedPower;
      if (first > target && res > 0.0)
        progress->update(std::clamp(std::log(first / res) / std::log(first / target), 0.0, 1.0));
      if (!std::isfinite(res)) throw std::runtime_error("non-finite radiosity after iteration " + std::to_string(it));
      if (refined == 0 && res <= opt.tolerance * emittedPower) {
        st.converged = true;
        break;
      }
    }
    if (!st.converged)
      progress->note("NOT CONVERGED after " + std::to_string(opt.maxIterations) + " iterations (raise --max-iterations)");
    progress->phase("energy balance");
    auto te = Clock::now();
    energy(st);
    st.tEnergy = since(te);
    st.elements = h.elements().size();
    st.leaves = static_cast<std::size_t>(std::count_if(h.elements().begin(), h.elements().end(), [](const Element& e) { return e.leaf(); }));
    st.clusters = h.clusters().size();
    st.links = links.size();
    st.rays = rays;
    st.linkBytes = links.capacity() * sizeof(Link);
    st.elementBytes = h.elements().capacity() * sizeof(Element) + B.capacity() * sizeof(Rgb) * 4;
    st.tTotal = since(t0);
    return st;
  }
};

Solver::Solver(const Scene& scene, Hierarchy& h, const Visibility& vis, const SolverOptions& opt, Extension* ext,
               Progress* progress)
    : impl_(std::make_unique<Impl>(scene, h, vis, opt, ext, progress)) {}
Solver::~Solver() = default;
SolveStats Solver::solve() { return impl_->solve(); }
const std::vector<Rgb>& Solver::radiosity() const { return impl_->B; }
const std::vector<Rgb>& Solver::irradiance() const { return impl_->Et; }
const HostView& Solver::view() const { return *impl_; }

}  // namespace hr
