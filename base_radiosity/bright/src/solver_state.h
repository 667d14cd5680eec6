// The solver's shared state, internal to base_radiosity: the per-node arrays every phase reads or
// writes (radiosity, irradiance, cluster intensity tables), the links, and the small helpers the
// phases share (a node's material, a sender's light toward a receiver). Each phase lives in a file of
// its own (transfer.cpp, refine.cpp, push_pull.cpp, energy_audit.cpp) and works on this state.
#pragma once
#include <hr/audit_estimators.h>
#include <hr/octamap.h>
#include <hr/phase_clock.h>
#include <hr/rng.h>
#include <hr/solver.h>

#include "memory_budget.h"

#include <atomic>
#include <chrono>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace hr::detail {

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
  float wkid[4] = {};   // visible kernel weight of each of the sender's four quadtree children
  float vsigma = 0.0f;  // standard error of the visible fraction from the link's shadow rays
  bool evaluated : 1 = false;
  bool measured : 1 = false;  // an overlapping link with a cluster end: its power was measured by rays (measureOverlap)
  bool capped : 1 = false;    // the oracle wanted it split and a memory budget kept it (capRound)
  bool readVisibility : 1 = false;  // the oracle's decision read `seenVisible` (refine.cpp)
  bool retraced : 1 = false;        // its coefficient was traced again, on other rays than `seenVisible`'s
  // The visible fraction its first trace found, in 1/kSeenScale (kSeenScale: every ray got
  // through): what the oracle reads for visibility, never the rays of the coefficient it keeps
  // (refine.cpp, seenPartly). In the padding, with the bits above: the link is no larger for it.
  std::uint8_t seenVisible = 0;
  // Between a push/pull and the next gather (when E is not read), E may hold the extension's share of
  // the sender's value toward an element receiver (SolverState::senderValue): 1 computed while the
  // sender was a leaf element or a cluster, 2 while it was an inner element; 0 none. In the padding:
  // the link is no larger for it.
  std::uint8_t extCache = 0;
  // Where in each sender child the receiver sees it: the visible-kernel-weighted mean of the rays'
  // ends about the child's area centroid, along the child's plane axes, in 1/127 of its radius.
  std::int8_t seen[4][2] = {};
};

static_assert(sizeof(Link) <= 100, "a link's size is most of a solve's memory: keep extCache and capped in the padding");

/// An element's in-plane axes, along its first edge and across it: the frame of its radiosity
/// gradient (SolverState::gradU, gradV) and of the links' `seen` offsets.
inline std::pair<Vec3, Vec3> planeAxes(const Polygon& p, const Vec3& n) {
  const Vec3 t1 = glm::normalize(p.v[1] - p.v[0]);
  return {t1, glm::cross(n, t1)};
}

/// Leaves new elements of a link array unwritten: the arrays are filled in parallel (refine.cpp,
/// grouping), so their pages are first touched by the threads that fill them. Value-initialising
/// them first was a serial sweep over every new page (a tenth of what refinement could not spread
/// over cores). Only for types with nothing to construct or destroy.
template <class T>
struct FillLater : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = FillLater<U>;
  };
  FillLater() = default;
  template <class U>
  FillLater(const FillLater<U>&) noexcept {}
  template <class U>
  void construct(U*) noexcept {
    static_assert(std::is_trivially_copyable_v<U> && std::is_trivially_destructible_v<U>);
  }
  template <class U, class... A>
  void construct(U* p, A&&... a) {
    ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
  }
};
using LinkArray = std::vector<Link, FillLater<Link>>;

/// Wall and CPU time of the phases, and how many distinct threads worked in each: a phase that
/// should be parallel but ran on one thread shows here (and fails a test).
/// Timed by hr::PhaseTimer (hr/phase_clock.h).
struct PhaseClock {
  double wall = 0.0, cpu = 0.0;
  std::atomic<std::uint64_t> threadMask{0};
  void sawThread() { markThread(threadMask); }  // call from inside the phase's parallel bodies
  int threads() const { return threadCount(threadMask); }
};

struct SolverState {
  SolverState(const Scene& s, Hierarchy& hi, const Visibility& v, const SolverOptions& o, Extension* e)
      : scene(s), h(hi), vis(v), opt(o), ext(e), patchPos(hi.patchOrder().size()) {
    for (std::uint32_t i = 0; i < patchPos.size(); ++i) patchPos[h.patchOrder()[i]] = i;
  }
  const Scene& scene;
  Hierarchy& h;
  const Visibility& vis;
  SolverOptions opt;
  Extension* ext;

  std::vector<std::uint32_t> patchPos;  // per patch: its place in Hierarchy::patchOrder (cluster membership)
  std::vector<Rgb> B, Eg, Et;         // per element: radiosity, gathered and total irradiance
  // Per element: the least-squares linear fit of what its leaves send (radiosity; unshot radiosity
  // while shooting) about its area centroid, W/m^2 per m along planeAxes (0 for leaves; push_pull.cpp).
  std::vector<Rgb> gradU, gradV;
  std::vector<float> Bmin, Bmax;      // per element: range of its leaves' radiosity (luminance, W/m^2)
  // Per element: the fraction of its area no coplanar patch covers (coplanar.h), 1 almost always;
  // below 1 on a floor element straddling the foot of a box that stands on it (transfer.cpp, push_pull.cpp).
  std::vector<float> open;
  // Shooting only (empty when gathering): per element, unshot radiosity (W/m^2) and its leaves' range.
  std::vector<Rgb> U;
  std::vector<float> Umin, Umax;
  bool shooting = false;  // a shooting pass is refining or transferring: senders send their unshot light
  std::vector<std::uint32_t> passShooters;  // the patches a shooting pass shot (its push visits them)
  std::atomic<std::size_t> pushSkipped{0};   // root patches the last shooting push left as they were
  std::vector<float> table;           // per large cluster: planar OctaMap of intensities, W/sr
  std::vector<std::uint32_t> tableSlot;  // per cluster: its table, or kNone when evaluated exactly
  std::vector<double> peak;           // per cluster: its largest intensity (luminance), W/sr
  std::vector<std::uint8_t> owned;    // per element: its subtree holds a surface the extension simulates
  std::vector<std::uint8_t> clusterOwned;
  std::vector<std::uint8_t> clusterEmits;  // per cluster: every patch in it emits (transfer.cpp's ray count)
  // How sharply simulated surfaces reflect (Extension::reflector), per material and per cluster (its
  // surfaces' largest albedo and narrowest lobe); empty without an extension that asks for it.
  std::vector<Reflector> materialReflector, clusterReflector;
  LinkArray links;            // sorted by receiver after refinement
  std::vector<std::uint32_t> groupStart;  // receivers' link ranges in links
  double emittedPower = 0.0;             // luminance, W
  RefineCap cap;          // a memory budget's limit on what refinement may make (memory_budget.h)
  bool capCut = false;    // the cap stopped some split during the latest refinement (reset per pass by the solver)
  // Whether the oracle refines shadow boundaries to its per-area budget (refine.cpp, shadowError):
  // under a memory budget only once the threshold is down to the requested eps, since a shadow's
  // detail is the finest a solve holds, and spent in the coarse first passes it took the memory that
  // lost or made energy needed (the glossy Soda Shoppe at 300 MB: -0.94 -> -1.5 % imbalance, and
  // -3.1 %, a failed audit, when the budget ranked splits by it too).
  bool shadows = true;
  double minArea = 0.0;
  double sceneArea = 0.0;  // the root patches' area, m^2 (refine.cpp: a partly visible inner sender's budget)
  std::atomic<std::uint64_t> rays{0}, evaluated{0};  // shadow rays; link evaluations
  std::atomic<std::uint64_t> samples{0};  // Illumination Samples handed to the gather hook (per iteration)
  PhaseClock clkVisibility, clkRefine, clkGather, clkPushPull, clkEnergy;

  /// What element senders send: radiosity, or unshot radiosity during a shooting pass (W/m^2), and
  /// the range of its leaves' values (luminance).
  const std::vector<Rgb>& sent() const { return shooting ? U : B; }
  /// What clusters send (their intensity tables, peaks and power): radiosity when gathering; in a
  /// shooting solve the unshot radiosity, since there a cluster sends only as a pass's shooter
  /// (shoot.cpp). Pulled so after every pass.
  const std::vector<Rgb>& clusterSource() const { return opt.iteration == Iteration::Shoot ? U : B; }
  float sentMin(std::uint32_t e) const { return shooting ? Umin[e] : Bmin[e]; }
  float sentMax(std::uint32_t e) const { return shooting ? Umax[e] : Bmax[e]; }
  /// The extension's light as senders send it: its total light, or its unshot light during a
  /// shooting pass (W/sr; Extension::intensity, meanIntensity, intensityBound and their unshot kin).
  Rgb extIntensity(NodeId n, const Vec3& dir) const {
    return shooting ? ext->unshotIntensity(n, dir) : ext->intensity(n, dir);
  }
  Rgb extMeanIntensity(NodeId n, std::span<const Vec3> polygon) const {
    return shooting ? ext->unshotMeanIntensity(n, polygon) : ext->meanIntensity(n, polygon);
  }
  Rgb extIntensityBound(NodeId n, const Vec3& axis, double cosHalfAngle) const {
    return shooting ? ext->unshotIntensityBound(n, axis, cosHalfAngle) : ext->intensityBound(n, axis, cosHalfAngle);
  }
  const Material& mat(std::uint32_t e) const { return scene.materials[h.patches()[h.element(e).patch].material]; }
  /// The area of element e no coplanar patch covers, m^2: what its radiosity and irradiance apply to.
  double openArea(std::uint32_t e) const { return h.element(e).area * double(open[e]); }
  /// The Illumination Sample a link brought this iteration: its direction and irradiance, the
  /// distance between the centres, hr::senderDiskRadius of the sender (a cluster as a face seen square
  /// on) and an element sender's normal and shape (a cluster has none).
  IncidentSample sampleOf(const Link& l) const {
    IncidentSample out{Vec3(l.dir), Rgb(l.E), glm::length(h.center(l.sender) - h.center(l.receiver)), 0.0};
    if (l.sender.isCluster()) {
      out.radius = senderDiskRadius(h.spread2(l.sender), 1.0);
      return out;
    }
    const Element& e = h.element(l.sender.index());
    out.radius = senderDiskRadius(h.spread2(l.sender), glm::dot(e.normal, Vec3(l.dir)));
    out.senderNormal = glm::vec3(e.normal);
    out.senderShape = e.shape;
    return out;
  }
  Rgb emitted(std::uint32_t e) const { return kPi * mat(e).emission; }
  /// Whether a node sends direct light: an emitting element, or a cluster made only of emitters
  /// (clusterEmits; transfer.cpp gives its links an emitter's shadow rays).
  bool emits(NodeId n) const {
    return n.isCluster() ? clusterEmits[n.index()] != 0 : luminance(emitted(n.index())) > 0.0;
  }
  /// A simulated node's Reflector (albedo 0 when none is known).
  Reflector reflector(NodeId n) const {
    if (materialReflector.empty()) return {};
    if (n.isCluster()) return clusterReflector[n.index()];
    return materialReflector[h.patches()[h.element(n.index()).patch].material];
  }
  bool isOwned(NodeId n) const { return n.isCluster() ? clusterOwned[n.index()] != 0 : owned[n.index()] != 0; }
  /// Clusters of at most this many patches send their exact Lambertian intensity (a sum of cosine
  /// lobes) instead of a table: more accurate, and 85 % of the Soda Shoppe's clusters need no table.
  static constexpr std::uint32_t kExactPatches = 16;
  const float* clusterTable(std::uint32_t c) const { return &table[std::size_t(tableSlot[c]) * OctaMap::kBins * 3]; }
  float* clusterTable(std::uint32_t c) { return &table[std::size_t(tableSlot[c]) * OctaMap::kBins * 3]; }
  /// Assigns table slots (clusters of more than kExactPatches patches) and sizes the tables.
  void allocateTables();
  /// A cluster's Lambertian exitant intensity toward unit dir, W/sr (of clusterSource).
  Rgb clusterIntensity(std::uint32_t c, const Vec3& dir) const;
  /// A cluster's Lambertian exitant power, W (its patches' clusterSource times their open areas).
  Rgb clusterPower(std::uint32_t c) const;

  /// Sizes the per-element arrays after subdivision; a new child starts with its parent's values
  /// so that refinement does not perturb the solution.
  void growArrays();
  /// The sender's quantity for a link: radiosity for elements (W/m^2), intensity toward the
  /// receiver for clusters (W/sr), the extension's share included.
  Rgb senderValue(const Link& l) const;
  /// The same, keeping the extension's share toward an element receiver in the link (Link::extCache)
  /// while gathering: refinement reads it twice (the oracle, the receiver pass) and the next gather
  /// once more, all from the same light, and each read integrated a glossy sender's distribution over
  /// the receiver (half of a glossy Soda Shoppe solve). The kept share is the float E holds, and so
  /// is a fresh one: the value is the same whichever caller computed it first.
  Rgb senderValue(Link& l) const;
  /// senderValue without the extension's share.
  Rgb hostValue(const Link& l) const;
  /// The extension's share of senderValue (zero without one or for a sender it does not simulate).
  Rgb extensionShare(const Link& l) const;
  /// The extension's share on an overlapping (measured) link, where a direction toward the
  /// receiver's centre means nothing: its sender's exitant power per area (element, W/m^2) or over
  /// 4 pi (cluster, W/sr), the units of hostValue there.
  Rgb extensionMeasured(const Link& l) const;
  /// The extension's intensity of the link's sender averaged over directions to an element
  /// receiver, W/sr.
  Rgb extensionOverReceiver(const Link& l) const;
  /// Whether a link's ends are far apart for the extension's light: (r_s + r_r) / d <= kFarField.
  bool farField(const Link& l) const;
  /// An element sender's extension share toward a near element receiver, in the link's radiosity
  /// unit: the flux its distribution sends into the receiver's solid angle, no more.
  Rgb extensionNearField(const Link& l) const;
  /// Sorts links by receiver (stable counting sort) and rebuilds groupStart.
  void groupByReceiver(LinkArray& v, std::vector<std::uint32_t>& start) const;
  /// A point on a node's surface (clusters: area-sampled over their patches), lifted off it.
  Vec3 pointOn(NodeId n, double u, double w, Rng& rng, Vec3& normal, std::uint32_t* patch = nullptr) const;
  Vec3 lifted(const Element& e, const Vec3& x) const { return x + e.normal * vis.epsilon(); }
};

/// A link's visibility may move at most this fraction of the emitted power (one standard error; or
/// eps if that is finer), whatever the refinement threshold: more rays, else a split (transfer.cpp,
/// refine.cpp).
constexpr double kVisibilityTolerance = 2e-4;
inline double visibilityTolerance(const SolverState& s) {
  return std::min(s.opt.eps, kVisibilityTolerance) * s.emittedPower;
}

/// The power a link would carry without occlusion, W (luminance): its sender's value times its
/// unoccluded transfer times the receiver's catching area.
double unoccludedPower(const SolverState& s, const Link& l);
/// The receiver's area that catches a link's light, m^2 (a cluster: a quarter of its surface).
double catchingArea(const SolverState& s, const Link& l);

/// Transfer evaluation of a new link: coefficient, bound, spread, direction, shadow rays. Returns the
/// number of rays traced. Thread-safe (reads the state, writes only the link).
/// `again`: the coefficient is traced afresh, on other rays than the first trace's, and
/// Link::seenVisible keeps the first trace's value.
int evaluateLink(const SolverState& s, Link& l, bool again = false);

/// Link::seenVisible's scale.
constexpr int kSeenScale = 254;

/// Whether a kept link needs measureOverlap: bounding spheres that overlap, (r_s + r_r) / d >= 1,
/// and an element sender with a cluster receiver (once), or a cluster sender whose link a memory
/// budget kept against the oracle (at every refinement pass, as what its patches send changes; the
/// oracle keeps others only when all the sender sends is under the threshold).
inline bool needsMeasure(const Link& l) {
  if (l.geom < 1.0f) return false;
  return l.sender.isCluster() ? l.capped : l.receiver.isCluster() && !l.measured;
}
/// Replaces such a link's far-field coefficient by one that carries the power its sender really sends
/// into the cluster, from cosine-distributed rays (transfer.cpp). Returns the rays traced.
int measureOverlap(const SolverState& s, Link& l);

/// One refinement pass over every link: evaluates new links (parallel), decides (parallel), splits
/// (serial structural step), until no link changes; then groups links by receiver. Returns splits.
std::size_t refineLinks(SolverState& s);

/// Gathers every link's light to its receiver (parallel over receivers), then calls the extension's
/// gather hook top-down (gather_hooks.cpp).
void gatherLinks(SolverState& s);
/// The extension's gather hook for every receiver holding simulated surfaces, top-down: parallel over
/// disjoint subtrees, a receiver after those above it.
void callGatherHooks(SolverState& s);
/// Pushes irradiance down and pulls radiosity and cluster intensities up (parallel over subtrees).
/// Gathering replaces each leaf's radiosity; shooting adds the pass's light to radiosity and unshot.
/// Gather: replace each leaf's light by the iteration's. Shoot: add the pass's light, then pull.
/// ShootLeaves: add the light of the receiver groups [groupBegin, groupEnd) to the leaves (and reflect
/// their samples) without pulling; ShootPull: pull what the pass's receivers and shooters changed,
/// adding nothing (shoot.cpp reflects a pass in batches, then pulls once).
enum class PushMode { Gather, Shoot, ShootLeaves, ShootPull };
void pushPull(SolverState& s, PushMode mode = PushMode::Gather, std::size_t groupBegin = 0,
              std::size_t groupEnd = std::size_t(-1));
/// Cluster intensities from the current radiosity alone (before the first gather).
void pullOnly(SolverState& s);

/// Throws InputError naming the scene when it cannot absorb any of some emitted channel (no finite
/// solution; absorption.cpp).
void checkCanAbsorb(const SolverState& s);
/// The message for a non-finite residual after `when` ("iteration 3"): the first element whose
/// host or extension light is not finite, named by object and material (nonfinite.cpp).
std::string nonFiniteWhere(const SolverState& s, const std::string& when);
/// The shooting iterations (shoot.cpp): passes until the unshot power is below the tolerance or
/// opt.maxIterations passes have run; fills st's history, iterations, converged and unshotW.
void shootPasses(SolverState& s, const HostView& view, Progress& progress, SolveStats& st);

/// The independent energy audit (see energy_audit.cpp).
audit::Totals auditEnergy(SolverState& s);

}  // namespace hr::detail
