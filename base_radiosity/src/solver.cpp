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
#include <chrono>
#include <cmath>
#include <cstdio>

namespace hr {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct Link {
  NodeId sender, receiver;
  float coef = 0.0f;    // element receiver: irradiance per unit sender quantity; cluster: E_perp per unit
  float spread = 0.0f;  // relative uncertainty of coef from its samples
  float geom = 0.0f;    // (r_s + r_r) / d for links with a cluster end, 0 otherwise
  float bound = 0.0f;   // coef with cosines replaced by 1: the oracle's upper bound
  glm::vec3 dir{0.0f};  // receiver -> sender, unit
  glm::vec3 E{0.0f};    // last transported irradiance (element) or normal irradiance (cluster), W/m^2
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
    if (ext) {
      bool own = l.sender.isCluster() ? clusterOwned[l.sender.index()] : owned[l.sender.index()];
      Rgb I;
      if (own && ext->exitantIntensity(l.sender, toRecv, I)) {
        if (l.sender.isCluster()) return I;
        const Element& e = h.element(l.sender.index());
        double c = glm::dot(e.normal, toRecv);
        return c > 1e-6 ? kPi * I / (e.area * c) : Rgb(0.0);
      }
    }
    if (l.sender.isCluster()) return OctaMap::lookup(&table[std::size_t(l.sender.index()) * OctaMap::kBins * 3], toRecv);
    return B[l.sender.index()];
  }

  // ---- sampling points on nodes ----------------------------------------------------------------
  Vec3 pointOn(NodeId n, double u, double w, Rng& rng) const {
    if (!n.isCluster()) return h.element(n.index()).poly.sample(u, w);
    const Cluster& c = h.cluster(n.index());
    const auto& pre = h.patchAreaPrefix();
    double a = pre[c.patchBegin] + u * (pre[c.patchEnd] - pre[c.patchBegin]);
    auto it = std::upper_bound(pre.begin() + c.patchBegin, pre.begin() + c.patchEnd + 1, a);
    std::size_t idx = std::clamp<std::size_t>(std::size_t(it - pre.begin()) - 1, c.patchBegin, c.patchEnd - 1);
    return h.patches()[h.patchOrder()[idx]].poly.sample(rng.uniform(), w);
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
    Vec3 cs = h.center(l.sender), cr = h.center(l.receiver);
    Vec3 d = cs - cr;
    double dist = glm::length(d);
    l.dir = glm::vec3(dist > 0.0 ? d / dist : Vec3(0, 0, 1));
    l.evaluated = true;
    bool ee = !l.sender.isCluster() && !l.receiver.isCluster();
    int n = 0;
    if (ee) {
      const Element& s = h.element(l.sender.index());
      const Element& r = h.element(l.receiver.index());
      if (s.patch == r.patch) return 0;
      // The coefficient: unoccluded point form factors averaged over kFfPoints stratified receiver
      // points (analytic, cheap), times the visible fraction from K rays weighted by form factor.
      constexpr int kFfPoints = 16;
      double fsum = 0.0;
      for (int k = 0; k < kFfPoints; ++k) {
        Vec3 x = r.poly.sample((k + rr.uniform()) / kFfPoints, rr.uniform());
        fsum += pointPolygonFormFactor(x, r.normal, s.poly, s.normal);
      }
      double fmean = fsum / kFfPoints;
      for (int k = 0; k < K; ++k) {
        Vec3 x = r.poly.sample((k + rr.uniform()) / K, rr.uniform());
        val[k] = pointPolygonFormFactor(x, r.normal, s.poly, s.normal);
        if (val[k] > 0.0) {
          from[n] = x;
          to[n] = s.poly.sample((k + rs.uniform()) / K, rs.uniform());
          ++n;
        }
      }
      vis.occluded(from, to, n, blocked);
      double wsum = 0.0, vsum = 0.0;
      int nvis = 0;
      for (int k = 0, j = 0; k < K; ++k) {
        if (val[k] <= 0.0) continue;
        bool b = blocked[j++];
        wsum += val[k];
        vsum += b ? 0.0 : val[k];
        nvis += b ? 0 : 1;
      }
      double V = wsum > 0.0 ? vsum / wsum : 1.0;
      l.coef = static_cast<float>(fmean * V);
      // The bound is the unoccluded transfer: a link whose few rays were all blocked may still be
      // partly visible, so it must be refined (or found small) rather than dropped.
      l.bound = static_cast<float>(fmean);
      // The oracle's variation comes from fixed points (corners pulled 1e-3 inward, and the centre),
      // not from the points that set the coefficient: deciding on the same random samples that set
      // the value would keep preferentially the links whose samples happen to agree, a bias.
      Vec3 c = r.center;
      double lo = pointPolygonFormFactor(c, r.normal, s.poly, s.normal), hi = lo;
      for (int k = 0; k < r.poly.n; ++k) {
        double f = pointPolygonFormFactor(r.poly.v[k] + 1e-3 * (c - r.poly.v[k]), r.normal, s.poly, s.normal);
        lo = std::min(lo, f);
        hi = std::max(hi, f);
      }
      double vspread = nvis < n ? 1.0 : 0.0;  // any blocked ray: visibility is uncertain
      l.spread = fmean > 0.0 ? static_cast<float>((hi - lo) / std::max(fmean, 1e-300) + vspread) : 0.0f;
      l.geom = 0.0f;
      return n;
    }
    // A cluster at one end: point kernel between centres over a bounded squared distance, visible
    // fraction from K rays between area-sampled surface points.
    for (int k = 0; k < K; ++k) {
      from[k] = pointOn(l.receiver, (k + rr.uniform()) / K, rr.uniform(), rr);
      to[k] = pointOn(l.sender, (k + rs.uniform()) / K, rs.uniform(), rs);
    }
    n = K;
    vis.occluded(from, to, n, blocked);
    int visible = 0;
    for (int k = 0; k < K; ++k) visible += blocked[k] ? 0 : 1;
    double V = double(visible) / K;
    double rs2 = h.radius(l.sender), rr2 = h.radius(l.receiver);
    double denom = dist * dist + rs2 * rs2 + rr2 * rr2;
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
    l.spread = visible < K ? 1.0f : 0.0f;
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
        } else if (l.coef > 0.0f) {
          kept.push_back(l);  // links that carry no light are dropped
        }
      }
      pending = std::move(next);
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
          if (ext) {
            bool own = recv.isCluster() ? clusterOwned[recv.index()] : owned[recv.index()];
            if (own) {
              Transfer t{l.sender, l.receiver, Vec3(l.dir), e};
              if (!recv.isCluster()) {
                double c = glm::dot(h.element(recv.index()).normal, Vec3(l.dir));
                t.normalIrradiance = c > 1e-3 ? e / c : e / 1e-3;
              }
              if (ext->gather(t)) {
                l.E = glm::vec3(0.0f);
                continue;
              }
            }
          }
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
      if (ext && owned[e]) ext->reflect(NodeId{e}, total);
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
    if (ext) ext->pushPull(*this);
  }

  void markOwned() {
    clusterOwned.assign(h.clusters().size(), 0);
    if (!ext) return;
    for (std::uint32_t p = 0; p < h.patches().size(); ++p)
      owned[p] = ext->handles(material(h.patches()[p].material)) ? 1 : 0;
    // Clusters are built with children after parents: a reverse sweep sees children first.
    for (std::size_t c = h.clusters().size(); c-- > 0;)
      for (NodeId k : h.cluster(static_cast<std::uint32_t>(c)).children)
        clusterOwned[c] |= k.isCluster() ? clusterOwned[k.index()] : owned[k.index()];
  }

  // ---- energy ---------------------------------------------------------------------------------
  void energy(SolveStats& st) {
    const auto& els = h.elements();
    std::vector<Rgb> esc(els.size(), Rgb(0.0)), abs(els.size(), Rgb(0.0));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, els.size(), 64), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        const Element& e = els[i];
        if (!e.leaf()) continue;
        abs[i] = e.area * (Rgb(1.0) - mat(static_cast<std::uint32_t>(i)).diffuse) * Et[i];
        if (maxComponent(B[i]) <= 0.0) continue;
        // Escaped power, measured independently of the links: cosine-distributed rays from the leaf.
        Rng rng(opt.seed ^ 0xE5CA9Eull, i);
        Vec3 t = std::abs(e.normal.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
        Vec3 u = glm::normalize(glm::cross(t, e.normal)), v = glm::cross(e.normal, u);
        int miss = 0;
        const int M = opt.escapeRays;
        const int side = std::max(1, static_cast<int>(std::lround(std::sqrt(double(M)))));
        for (int k = 0; k < M; ++k) {
          // Uniform over the leaf, stratified over the cosine-weighted hemisphere (2D grid).
          Vec3 o = e.poly.sample(rng.uniform(), rng.uniform());
          int sx = k % side, sy = (k / side) % side;
          double a = 2.0 * kPi * (sx + rng.uniform()) / side, s = std::sqrt((sy + rng.uniform()) / side);
          Vec3 d = s * std::cos(a) * u + s * std::sin(a) * v + std::sqrt(std::max(0.0, 1.0 - s * s)) * e.normal;
          if (vis.escapes(o + e.normal * vis.epsilon(), d)) ++miss;
        }
        esc[i] = B[i] * e.area * (double(miss) / M);
      }
    });
    for (std::size_t i = 0; i < els.size(); ++i) {
      st.escapedW += esc[i];
      st.absorbedW += abs[i];
    }
    rays += std::uint64_t(opt.escapeRays) * std::count_if(els.begin(), els.end(), [](const Element& e) { return e.leaf(); });
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
