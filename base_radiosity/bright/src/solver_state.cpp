// Helpers every solver phase shares: array growth after subdivision, a sender's light toward a
// receiver, grouping links by receiver, points on nodes.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>

#include <hr/kernel.h>

#include "solver_state.h"

#include <utility>

#include "counting_sort.h"

namespace hr::detail {

namespace {
/// The fraction of an element's area outside every coplanar cover, from a fixed 16 x 16 grid of
/// area-uniform points (deterministic).
float openFraction(const Visibility& vis, const Element& e) {
  constexpr int kGrid = 16;
  int open = 0;
  for (int a = 0; a < kGrid; ++a)
    for (int b = 0; b < kGrid; ++b)
      open += vis.coverOf(e.patch, e.poly.sample((a + 0.5) / kGrid, (b + 0.5) / kGrid)) == kNone ? 1 : 0;
  return static_cast<float>(open) / float(kGrid * kGrid);
}
}  // namespace

void SolverState::growArrays() {
  std::size_t n = h.elements().size();
  std::size_t old = B.size();
  B.resize(n);
  Eg.resize(n, Rgb(0.0));
  Et.resize(n, Rgb(0.0));
  gradU.resize(n, Rgb(0.0));
  gradV.resize(n, Rgb(0.0));
  owned.resize(n, 0);
  Bmin.resize(n);
  Bmax.resize(n);
  open.resize(n, 1.0f);
  const bool shoot = opt.iteration == Iteration::Shoot;
  if (shoot) U.resize(n), Umin.resize(n), Umax.resize(n);
  // New elements' parents are older elements (refinement subdivides leaves that exist, then grows;
  // a fresh hierarchy is all roots): each new entry reads only entries that exist.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(old, n, 1024), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const Element& e = h.element(static_cast<std::uint32_t>(i));
      assert(e.parent == kNone || e.parent < old);
      B[i] = e.parent == kNone ? emitted(static_cast<std::uint32_t>(i)) : B[e.parent];
      Et[i] = e.parent == kNone ? Rgb(0.0) : Et[e.parent];
      owned[i] = e.parent == kNone ? 0 : owned[e.parent];
      if (vis.partlyCovered(e.patch)) open[i] = openFraction(vis, e);
      // A wholly covered child has no light but its emission (push_pull.cpp), whatever its parent's
      // open part had: shooting adds to what a child inherits, and would keep that for good.
      if (e.parent != kNone && open[i] == 0.0f) B[i] = emitted(static_cast<std::uint32_t>(i));
      Bmin[i] = Bmax[i] = static_cast<float>(luminance(B[i]));
      if (shoot) {
        // A root's unshot light is its emission; a child's is its parent's (unshot radiosity per area).
        U[i] = e.parent == kNone ? emitted(static_cast<std::uint32_t>(i)) : U[e.parent];
        Umin[i] = Umax[i] = static_cast<float>(luminance(U[i]));
      }
    }
  });
}

Rgb SolverState::hostValue(const Link& l) const {
  if (l.sender.isCluster()) {
    return l.measured ? clusterPower(l.sender.index()) / (4.0 * kPi) : clusterIntensity(l.sender.index(), -Vec3(l.dir));
  }
  const Element& e = h.element(l.sender.index());
  double ws = l.wkid[0] + l.wkid[1] + l.wkid[2] + l.wkid[3];
  if (e.leaf() || !(ws > 0.0)) return sent()[l.sender.index()];
  // An inner sender sends the visibility-weighted mean of its children (docs/solver.md), each
  // child's value taken where the receiver sees it: its radiosity's linear fit at the link's
  // seen offset. The children's means alone missed that the parts of a sender nearest its
  // receiver tend to be the ones the receiver lights (1 % of the Cornell box's light was lost).
  // While shooting, the fit is of the unshot radiosity (push_pull.cpp).
  Rgb v(0.0);
  for (int k = 0; k < 4; ++k) {
    const std::uint32_t c = e.firstChild + k;
    const double r = h.element(c).radius / 127.0;
    v += double(l.wkid[k]) * glm::max(Rgb(0.0), sent()[c] + gradU[c] * (r * l.seen[k][0]) + gradV[c] * (r * l.seen[k][1]));
  }
  return v / ws;
}

Rgb SolverState::extensionShare(const Link& l) const {
  if (!ext || !isOwned(l.sender)) return Rgb(0.0);
  // Additive: the extension's directional share joins the host's Lambertian light. Toward an
  // element receiver it is the mean over the receiver's solid angle (Extension::meanIntensity):
  // a value toward a few points aliased against a narrow lobe, and a spot came out 7 % dark.
  if (!l.sender.isCluster() && !l.receiver.isCluster() && !farField(l)) return extensionNearField(l);
  if (l.measured) return extensionMeasured(l);
  const Vec3 toRecv = -Vec3(l.dir);
  Rgb I = l.receiver.isCluster() ? extIntensity(l.sender, toRecv) : extensionOverReceiver(l);
  if (l.sender.isCluster()) return I;
  const Element& e = h.element(l.sender.index());
  double c = glm::dot(e.normal, toRecv);
  return c > 1e-6 ? kPi * I / (e.area * c) : Rgb(0.0);
}

Rgb SolverState::senderValue(const Link& l) const { return hostValue(l) + extensionShare(l); }

Rgb SolverState::senderValue(Link& l) const {
  if (!ext || shooting || l.receiver.isCluster() || !isOwned(l.sender)) return senderValue(std::as_const(l));
  const std::uint8_t state = l.sender.isCluster() || h.element(l.sender.index()).leaf() ? 1 : 2;
  if (l.extCache != state) {
    l.E = glm::vec3(extensionShare(l));
    l.extCache = state;
  }
  return hostValue(l) + Rgb(l.E);
}

Rgb SolverState::extensionMeasured(const Link& l) const {
  // An overlapping element-to-cluster link (measureOverlap) carries the fraction F of the sender's
  // cosine-distributed rays that reach the cluster, times A_s and the value: for the host's
  // Lambertian light that is F times its power. The extension's share as elsewhere, pi I / (A c)
  // toward the cluster's centre, is the power a Lambertian sender of that intensity would have: a
  // mirror's lobe pointed at the centre (the centre can be anywhere, the sender lies inside the
  // cluster) made it 10-40 times the lobe's power, and two stainless discs 5 mm apart in the glossy
  // Soda Shoppe, whose links a memory budget left unrefined, fed each other 4.4 times what they sent
  // until the solve diverged. So the share is the sender's whole power in the link's unit, as the
  // host's own value on such a link (hostValue): per area for an element, over 4 pi for a cluster;
  // delivered as its Lambertian light is, never more than F of it.
  const Rgb power = shooting ? ext->unshotPower(l.sender) : ext->totalPower(l.sender);
  const double per = l.sender.isCluster() ? 4.0 * kPi : h.element(l.sender.index()).area;
  return allFinite(power) && per > 0.0 ? glm::max(power, Rgb(0.0)) / per : Rgb(0.0);
}

/// (r_s + r_r) / d below which a glossy sender's light is averaged over its receiver.
constexpr double kFarField = 0.25;

bool SolverState::farField(const Link& l) const {
  const double d = glm::length(h.center(l.sender) - h.center(l.receiver));
  return d > 0.0 && (h.radius(l.sender) + h.radius(l.receiver)) / d <= kFarField;
}

namespace {
/// Solid angle of a convex spherical polygon of unit directions (a fan of triangles, Van Oosterom
/// and Strackee's formula per triangle).
double polygonSolidAngle(const Vec3* d, int n) {
  double sum = 0.0;
  for (int k = 1; k + 1 < n; ++k) {
    const Vec3 &a = d[0], &b = d[k], &c = d[k + 1];
    double num = std::abs(glm::dot(a, glm::cross(b, c)));
    double den = 1.0 + glm::dot(a, b) + glm::dot(b, c) + glm::dot(c, a);
    sum += 2.0 * std::atan2(num, den);
  }
  return sum;
}
}  // namespace

Rgb SolverState::extensionNearField(const Link& l) const {
  // An element sender close to an element receiver. The far-field rule (the intensity toward the
  // receiver's centre times pi / (A cos), turned into irradiance by the link's form factor) treats
  // the receiver as a point: near a wide receiver it hands all of the receiver's solid angle the
  // value of the one direction toward its centre. Against a lobe narrower than the receiver (Phong
  // 10^4: all the light in one Haar leaf cell of ~0.025 sr, the receiver ~1 sr) that delivered tens
  // of times the power the sender sends that way whenever the centre direction fell in the lobe's
  // cell: two facing near-mirrors made 3x the emitted power, and the glossy Soda Shoppe's residual
  // grew ~10x per iteration.
  // So the link carries the flux Phi the sender's distribution sends into the receiver's solid angle
  // (mean I over the polygon of directions times its solid angle: exact for Haar), with only the
  // geometry's own correction, as the host does for its Lambertian light: the sender's form factor
  // over the projected solid angle Omega_proj = pi F of the receiver from the points Phi was taken at.
  // The value in the link's radiosity unit is v = pi Phi / (A_s Omega_proj), and the receiver gets
  // V F_sr pi Phi / Omega_proj: exactly the Lambertian transfer for a cosine lobe, and never more than
  // the lobe sends into the receiver's directions times a factor of geometry alone (the flux alone
  // lost 3.6 % of a glossy furnace, whose neighbouring faces see more of each other than from their
  // centres).
  const Element& re = h.element(l.receiver.index());
  const Element& se = h.element(l.sender.index());
  // The flux node n's distribution sends into the receiver seen from `from`, times wFlux, and the
  // projected solid angle pi F of the receiver there, times wProj.
  Rgb flux(0.0);
  double projected = 0.0;
  auto addFrom = [&](NodeId n, const Vec3& from, double wFlux, double wProj) {
    Vec3 dirs[4];
    for (int k = 0; k < re.poly.n; ++k) {
      Vec3 d = re.poly.v[k] - from;
      double len = glm::length(d);
      if (!(len > 0.0)) return;  // a receiver corner at the point: no solid angle
      dirs[k] = d / len;
    }
    const double omega = polygonSolidAngle(dirs, re.poly.n);
    const double proj = kPi * pointPolygonFormFactor(from, se.normal, re.poly, re.normal);
    if (!(omega > 0.0) || !(proj > 0.0)) return;
    flux += wFlux * extMeanIntensity(n, std::span<const Vec3>(dirs, std::size_t(re.poly.n))) * omega;
    projected += wProj * proj;
  };
  // The flux and the projected solid angle are both taken at four points of the sender (a leaf's
  // quarters' centres, with its one distribution; an inner element's children's centres, each with its
  // own, whose fluxes add), and the link carries the ratio of the sums. From any one point the fluxes
  // into all the receivers around it add up to what the point sends, so over the points they do too;
  // a ratio per point (the centre alone, or each child on its own) weighed each receiver's flux by that
  // point's geometry against the whole sender's form factor, and a glossy furnace lost 2.2 % of its
  // glossy light at eps 2e-3 (3.7 % with senders as disks) that way.
  if (se.leaf()) {
    for (const Polygon& q : se.poly.subdivide()) {
      const double w = q.area() / se.area;
      addFrom(l.sender, q.centroid(), w, w);
    }
  } else {
    for (NodeId kid : h.children(l.sender)) {
      const Element& k = h.element(kid.index());
      addFrom(kid, k.center, 1.0, k.area / se.area);
    }
  }
  const Rgb v = projected > 0.0 ? kPi * flux / (se.area * projected) : Rgb(0.0);
  return allFinite(v) ? glm::max(v, Rgb(0.0)) : Rgb(0.0);
}

Rgb SolverState::extensionOverReceiver(const Link& l) const {
  const Polygon& r = h.element(l.receiver.index()).poly;
  // The receiver seen from a node's centre, as the polygon of directions to its corners.
  auto seenFrom = [&](NodeId n) {
    const Vec3 from = h.center(n);
    Vec3 dirs[4];
    for (int k = 0; k < r.n; ++k) {
      Vec3 d = r.v[k] - from;
      double len = glm::length(d);
      if (!(len > 0.0)) return extIntensity(n, -Vec3(l.dir));
      dirs[k] = d / len;
    }
    return extMeanIntensity(n, std::span<const Vec3>(dirs, std::size_t(r.n)));
  };
  // An inner element sends as its four children, each from its own centre: the parent's pulled
  // distribution is a coarser sum, and a wide sender's parts see a near receiver from different
  // directions (the spots a 0.6 m reflector threw on a wall 3.5 m away shifted by 4 cm).
  // Only in the far field: the link turns the mean intensity into radiosity with the cosine of the
  // centre direction, which the polygon's mean does not match when the receiver fills a wide angle
  // (neighbouring faces of a glossy furnace lost 1 % more energy that way).
  if (!farField(l)) return extIntensity(l.sender, -Vec3(l.dir));
  if (!l.sender.isCluster() && !h.element(l.sender.index()).leaf()) {
    Rgb sum(0.0);
    for (NodeId kid : h.children(l.sender)) sum += seenFrom(kid);
    return sum;
  }
  return seenFrom(l.sender);
}

void SolverState::allocateTables() {
  tableSlot.assign(h.clusters().size(), kNone);
  std::uint32_t n = 0;
  for (std::uint32_t c = 0; c < h.clusters().size(); ++c)
    if (h.cluster(c).patchEnd - h.cluster(c).patchBegin > kExactPatches) tableSlot[c] = n++;
  table.assign(std::size_t(n) * OctaMap::kBins * 3, 0.0f);
  peak.assign(h.clusters().size(), 0.0);
}

Rgb SolverState::clusterPower(std::uint32_t c) const {
  const Cluster& cl = h.cluster(c);
  Rgb P(0.0);
  for (std::uint32_t i = cl.patchBegin; i < cl.patchEnd; ++i) {
    const std::uint32_t p = h.patchOrder()[i];  // the root element of patch p has index p
    P += clusterSource()[p] * openArea(p);
  }
  return P;
}

Rgb SolverState::clusterIntensity(std::uint32_t c, const Vec3& dir) const {
  if (tableSlot[c] != kNone) return OctaMap::lookup(clusterTable(c), dir);
  const Cluster& cl = h.cluster(c);
  Rgb I(0.0);
  for (std::uint32_t i = cl.patchBegin; i < cl.patchEnd; ++i) {
    std::uint32_t p = h.patchOrder()[i];  // the root element of patch p has index p
    double cs = glm::dot(h.patches()[p].normal, dir);
    if (cs > 0.0) I += clusterSource()[p] * (openArea(p) * cs / kPi);
  }
  return I;
}

void SolverState::groupByReceiver(LinkArray& v, std::vector<std::uint32_t>& start) const {
  // Stable counting sort on a dense key (elements first, then clusters): O(links + nodes), where a
  // comparison sort of 90-byte links was a tenth of the solve; in parallel blocks (counting_sort.h),
  // with one new array as the serial version had.
  const std::size_t E = h.elements().size();
  auto key = [&](std::size_t i) {
    const NodeId r = v[i].receiver;
    return r.isCluster() ? E + r.index() : std::size_t(r.index());
  };
  LinkArray out(v.size());
  start = countingSort(v.size(), E + h.clusters().size(), key, [&](std::size_t i, std::uint32_t p) { out[p] = v[i]; });
  v = std::move(out);
}

/// A point on a node's surface (not lifted: see liftPair in transfer.cpp). Shadow-ray ends are
/// lifted off their surfaces along the normal: rays from points within ~1e-4 of a neighbouring face
/// (a cube's edge) otherwise graze that face in single precision and report a hit, which made every
/// link of such a point look blocked.
Vec3 SolverState::pointOn(NodeId n, double u, double w, Rng& rng, Vec3& normal, std::uint32_t* patch) const {
  if (!n.isCluster()) {
    const Element& e = h.element(n.index());
    normal = e.normal;
    if (patch) *patch = e.patch;
    return e.poly.sample(u, w);
  }
  const Cluster& c = h.cluster(n.index());
  const auto& pre = h.patchAreaPrefix();
  double a = pre[c.patchBegin] + u * (pre[c.patchEnd] - pre[c.patchBegin]);
  auto it = std::upper_bound(pre.begin() + c.patchBegin, pre.begin() + c.patchEnd + 1, a);
  std::size_t idx = std::clamp<std::size_t>(std::size_t(it - pre.begin()) - 1, c.patchBegin, c.patchEnd - 1);
  const Patch& p = h.patches()[h.patchOrder()[idx]];
  normal = p.normal;
  if (patch) *patch = h.patchOrder()[idx];
  return p.poly.sample(rng.uniform(), w);
}

}  // namespace hr::detail
