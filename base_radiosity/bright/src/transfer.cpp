// Transfer evaluation of one link: the coefficient that turns the sender's quantity into the
// receiver's irradiance, its unoccluded bound, its relative spread for the oracle and the shadow
// rays that set its visible fraction. docs/solver.md explains each choice.
#include <hr/audit_estimators.h>
#include <hr/kernel.h>

#include <algorithm>
#include <array>

#include "solver_state.h"

namespace hr::detail {
namespace {

/// cos cos / r^2 between two surface points (up to 1/pi), 0 unless they face each other: the
/// weight of a shadow ray in a link's visible fraction.
double pointKernel(const Vec3& x, const Vec3& nx, const Vec3& y, const Vec3& ny) {
  Vec3 xy = y - x;
  double d2 = glm::dot(xy, xy), cx = glm::dot(nx, xy), cy = -glm::dot(ny, xy);
  return cx > 0.0 && cy > 0.0 && d2 > 0.0 ? cx * cy / (d2 * d2) : 0.0;
}

constexpr int kMaxRays = 256;
/// Shadow rays at least, on a link whose receiver is partly under a coplanar cover (evaluateLink).
constexpr int kCoverRays = 32;
/// Shadow rays at least, on a link to an element whose sender emits: an emitting element, or a
/// cluster made only of emitters (evaluateLink).
constexpr int kEmitterRays = 32;
/// Draws per receiver point to find the open part of a partly covered receiver.
constexpr int kOpenTries = 16;

/// The outcome of a link's shadow rays: how many faced each other and how many of those got through.
struct RayCount {
  int traced = 0, facing = 0, visible = 0;
};

RayCount trace(const SolverState& s, Link& l, double dist, int K, bool again);

/// Lifts the two ends of a shadow ray off their surfaces (see SolverState::pointOn for why), each by
/// the visibility epsilon or a quarter of its height above the other end's plane if that is less:
/// two surfaces closer than the epsilon (facing lamps 1e-6 m apart) would otherwise be lifted past
/// each other and see each other through their own backs.
void liftPair(const SolverState& s, const Vec3& x, const Vec3& nx, const Vec3& y, const Vec3& ny, Vec3& from, Vec3& to) {
  const double eps = s.vis.epsilon();
  double hx = glm::dot(nx, y - x), hy = glm::dot(ny, x - y);
  from = x + nx * std::min(eps, 0.25 * std::max(hx, 0.0));
  to = y + ny * std::min(eps, 0.25 * std::max(hy, 0.0));
}

/// Receiver points at which each sender child's form factor is taken (childWeights): at most 16,
/// and 4 on far links.
constexpr int kChildWeightPoints = 16, kFarChildWeightPoints = 4;
/// Far links: (r_s + r_r) / d below these, the integrands over the two elements are smooth enough
/// for a cheaper estimate (evaluateElementLink: the quadrature's order, the children's shares, where
/// a child is seen).
constexpr double kFarReach = 0.2, kMidReach = 0.3;

/// Each sender child's share of the link as the receiver sees it (Link::wkid): the child's form
/// factor from the receiver, averaged over `points` of the rays' nx receiver points xs spread evenly
/// through them (the points are stratified in order, so the first few share a corner), times the
/// visible fraction
/// of the rays that ended in it, over the four children's form factors. The share was the visible
/// point kernel of the child's one ray (at 4 rays per link) over all rays' kernels: a ratio of
/// heavy-tailed samples where a sender meets its receiver (a block's face and the floor at its
/// foot: cos cos / r^2 without bound), which on average understated the child at the contact and
/// lit the Cornell box's short block 0.4 % too much (mean of three seeds). val, blocked: the rays'
/// kernels (0 where not traced) and, for the traced ones in order, their outcomes.
void childWeights(const Element& re, const Element& se, const std::array<Polygon, 4>& kids,
                  const Vec3* xs, int nx, int points, bool far, const double* val, const bool* blocked, int K,
                  float* wkid) {
  double F[4] = {0, 0, 0, 0}, seen[4] = {0, 0, 0, 0}, vis[4] = {0, 0, 0, 0};
  Vec3 kc[4];
  double kr[4];
  points = std::min(points, nx);
  if (far) {
    // Far apart, a child's form factor is its area times the point kernel at its area centroid, up
    // to terms of second order in its radius over d (grazing views aside, where both are small):
    // 16 contour integrals were most of a far link's own work (images moved by 1.3e-6).
    double area[4];
    for (int q = 0; q < 4; ++q) kc[q] = kids[q].areaCentroid(), area[q] = kids[q].area();
    for (int m = 0; m < points; ++m)
      for (int q = 0; q < 4; ++q)
        F[q] += pointKernel(xs[m * nx / points], re.normal, kc[q], se.normal) * area[q];
  } else {
    for (int q = 0; q < 4; ++q) kc[q] = kids[q].centroid(), kr[q] = kids[q].radius();
    for (int m = 0; m < points; ++m)
      for (int q = 0; q < 4; ++q)
        F[q] += pointPolygonFormFactor(xs[m * nx / points], re.normal, kids[q], se.normal, kc[q], kr[q]);
  }
  double all = 0.0, open = 0.0;
  for (int k = 0, j = 0; k < K; ++k) {
    if (val[k] <= 0.0) continue;
    const bool b = blocked[j++];
    seen[k % 4] += val[k], all += val[k];
    vis[k % 4] += b ? 0.0 : val[k], open += b ? 0.0 : val[k];
  }
  const double Fsum = F[0] + F[1] + F[2] + F[3];
  for (int q = 0; q < 4; ++q) {
    // A child no ray reached takes the link's visible fraction.
    const double V = seen[q] > 0.0 ? vis[q] / seen[q] : all > 0.0 ? open / all : 0.0;
    wkid[q] = static_cast<float>(Fsum > 0.0 ? F[q] * V / Fsum : 0.0);
  }
}

RayCount evaluateElementLink(const SolverState& s, Link& l, Rng& rr, Rng& rs, int K) {
  K = std::clamp(K, 1, kMaxRays);
  Vec3 from[kMaxRays], to[kMaxRays];
  bool blocked[kMaxRays];
  double val[kMaxRays];
  bool hidden[kMaxRays];
  for (int k = 0; k < K; ++k) from[k] = to[k] = Vec3(0.0);  // (quiets GCC's maybe-uninitialized)
  const Element& se = s.h.element(l.sender.index());
  const Element& re = s.h.element(l.receiver.index());
  if (se.patch == re.patch) return {};
  // Wholly under a coplanar cover: no light arrives; the link, its bound 0, is dropped.
  if (s.open[l.receiver.index()] == 0.0f) return {};
  // The oracle's variation comes from fixed points (corners pulled 1e-3 inward, and the centre),
  // not from the points that set the coefficient: deciding on the same random samples that set
  // the value would keep preferentially the links whose samples happen to agree, a bias.
  Vec3 c = re.center;
  const Vec3 sc = se.poly.centroid();
  const double sr = se.poly.radius();
  double lo = pointPolygonFormFactor(c, re.normal, se.poly, se.normal, sc, sr), hi = lo;
  l.at[4] = l.at[3] = static_cast<float>(lo);
  for (int k = 0; k < re.poly.n; ++k) {
    double f = pointPolygonFormFactor(re.poly.v[k] + 1e-3 * (c - re.poly.v[k]), re.normal, se.poly, se.normal, sc, sr);
    l.at[k] = static_cast<float>(f);
    lo = std::min(lo, f);
    hi = std::max(hi, f);
  }
  // The coefficient: the unoccluded form factor averaged by Gauss-Legendre quadrature
  // (deterministic: a jittered 4x4 grid left 5 % errors on links across a shared edge, where the
  // point form factor climbs steeply towards 1/2), times the visible fraction from K rays weighted
  // by form factor. The average is taken over the smaller of the two elements and converted by
  // reciprocity, A_r F_rs = A_s F_sr: a small bright sender close to a large receiver makes the
  // receiver's integrand a narrow peak that quadrature points on the receiver miss (36 % of a
  // lamp's power went missing 0.1 m above a plate), while over the small sender it is smooth.
  // Far apart, the integrand is smooth enough for fewer points: on three lights' 23,017 lit links,
  // against order 8, order 2 erred at most 1.9e-5 (relative) where the radii sum to under 0.2 of
  // the centres' distance (73 % of the links) and order 3 at most 2.8e-6 under 0.3 (81 %), far below
  // the visible fraction's noise; that halves the form factor's share of a solve (37 %, perf).
  const double reach = (s.h.radius(l.sender) + s.h.radius(l.receiver)) / glm::length(se.center - re.center);
  const int order = reach < kFarReach ? 2 : reach < kMidReach ? 3 : hi - lo > 0.5 * hi ? 6 : 4;
  double fmean = se.area < re.area
                     ? se.area / re.area * meanFormFactor(se.poly, se.normal, re.poly, re.normal, order)
                     : meanFormFactor(re.poly, re.normal, se.poly, se.normal, order);
  // Sender points: ray k lands in the sender's quadtree child k % 4 (stratified inside it), so
  // that the visible kernel weight of each child is known (see senderValue).
  const auto kidsPoly = se.poly.subdivide();
  const int perKid = (K + 3) / 4;
  // Per polygon, not per ray: how sample() splits it, and each child's share of the kernel's weight.
  const double reShare = re.poly.firstShare();
  double kidShare[4], kidScale[4];
  for (int q = 0; q < 4; ++q) {
    kidShare[q] = kidsPoly[q].firstShare();
    kidScale[q] = 4.0 * kidsPoly[q].area() / se.area;
  }
  Vec3 ends[kMaxRays], xs[kMaxRays];
  int n = 0;
  // A receiver partly under a coplanar patch (coplanar.h; a floor element at a box's foot): its
  // irradiance is its open part's mean (SolverState::open). Its points are drawn from the open part
  // (rejection against the cover), and its form factor is the mean of their exact point form
  // factors: the whole element's quadrature counted the covered part (the box's own face sends
  // nothing there), and rescaling that by the rays' open share was a ratio of counts, off by 5-12 %
  // on single elements. A point that finds no open spot in kOpenTries draws is not used.
  const bool partly = s.open[l.receiver.index()] < 1.0f;
  double openF = 0.0;
  int openRays = 0, nx = 0;
  for (int k = 0; k < K; ++k) {
    Vec3 x = re.poly.sample((k + rr.uniform()) / K, rr.uniform(), reShare);
    if (partly) {
      for (int t = 1; t < kOpenTries && s.vis.coverOf(re.patch, x) != kNone; ++t)
        x = re.poly.sample(rr.uniform(), rr.uniform(), reShare);
      if (s.vis.coverOf(re.patch, x) != kNone) {
        val[k] = 0.0;
        continue;
      }
      openF += pointPolygonFormFactor(x, re.normal, se.poly, se.normal, sc, sr);
      ++openRays;
    }
    xs[nx++] = x;  // the receiver points childWeights averages over
    Vec3 y = kidsPoly[k % 4].sample((k / 4 + rs.uniform()) / perKid, rs.uniform(), kidShare[k % 4]);
    ends[k] = y;
    val[k] = pointKernel(x, re.normal, y, se.normal) * kidScale[k % 4];
    if (val[k] > 0.0 && s.vis.coverOf(se.patch, y) != kNone) {
      // A sender end under a coplanar patch is hidden: a blocked ray without tracing it.
      from[n] = to[n] = Vec3(0.0);
      hidden[n++] = true;
      continue;
    }
    if (val[k] > 0.0) {
      hidden[n] = false;
      liftPair(s, x, re.normal, y, se.normal, from[n], to[n]);
      ++n;
    }
  }
  s.vis.occluded(from, to, n, blocked);
  if (s.opt.testOnlyUnblockedShadowRays) std::fill(blocked, blocked + n, false);  // (test only: SolverOptions)
  for (int j = 0; j < n; ++j) blocked[j] = blocked[j] || hidden[j];
  // The visible fraction weights each ray by the point-to-point kernel cos cos / r^2: weighting
  // by area alone took an occluder that hides the far half of a sender for hiding half of the
  // transfer, and a thin light panel under a ceiling cost the room 1 % of its power.
  double wsum = 0.0, vsum = 0.0;
  int nvis = 0;
  double kidw[4] = {0, 0, 0, 0};
  Vec3 kidp[4] = {Vec3(0.0), Vec3(0.0), Vec3(0.0), Vec3(0.0)};
  bool kidHid[4] = {false, false, false, false};
  for (int k = 0, j = 0; k < K; ++k) {
    if (val[k] <= 0.0) continue;
    bool b = blocked[j++];
    wsum += val[k];
    vsum += b ? 0.0 : val[k];
    kidw[k % 4] += b ? 0.0 : val[k];
    kidp[k % 4] += b ? Vec3(0.0) : val[k] * ends[k];
    kidHid[k % 4] = kidHid[k % 4] || b;
    nvis += b ? 0 : 1;
  }
  // Far apart (kFarReach, as for the quadrature order above) the children's form factors change
  // little across the receiver, and four points set their shares: on links of 16 rays or more
  // (emitters' 32) sixteen made the children's 64 point form factors most of three lights'
  // form-factor time at eps 3.5e-5 (its solve 0.50 -> 0.43 s).
  const int childPoints = reach < kFarReach ? kFarChildWeightPoints : kChildWeightPoints;
  childWeights(re, se, kidsPoly, xs, nx, childPoints, reach < kFarReach, val, blocked, K, l.wkid);
  // Where the receiver sees each child: with the children's radiosity fits (push_pull.cpp) this
  // carries the same estimate, visible kernel over the ray ends, below the children's means.
  // Far apart (kMidReach), a child none of whose rays was blocked is seen whole, and its
  // kernel-weighted centroid comes from fixed points (its quarters' centroids, seen from the
  // receiver's centre): at 4 rays per link its one random ray end moved the value along the fit's
  // gradient by up to the child's radius from seed to seed, most of three lights' seed noise on its
  // wall (1.8 % of its pixels). Near, the kernel changes across the receiver, which points from its
  // centre do not see, so the rays' ends (spread over the receiver too) are kept there; fixed points
  // everywhere widened the Cornell box's short block's seed spread (+0.62 to +1.08 % against +0.76
  // to +0.88 % for seeds 1-4) and broke its 1 % bar on seed 1.
  for (int k = 0; k < 4; ++k) {
    if (kidw[k] <= 0.0) continue;
    const Polygon& kid = kidsPoly[k];
    const auto [t1, t2] = planeAxes(kid, se.normal);
    Vec3 at = kidp[k] / kidw[k];
    if (!kidHid[k] && reach < kMidReach) {
      double w = 0.0;
      Vec3 p(0.0);
      for (const Polygon& q : kid.subdivide()) {
        const Vec3 y = q.areaCentroid();
        const double kq = pointKernel(c, re.normal, y, se.normal) * q.area();
        w += kq, p += kq * y;
      }
      if (w > 0.0) at = p / w;
    }
    const Vec3 off = at - kid.areaCentroid();
    const double r = kid.radius();
    for (int a = 0; a < 2; ++a) {
      const double u = r > 0.0 ? glm::dot(off, a == 0 ? t1 : t2) / r : 0.0;
      l.seen[k][a] = static_cast<std::int8_t>(std::lround(127.0 * std::clamp(u, -1.0, 1.0)));
    }
  }
  double V = wsum > 0.0 ? vsum / wsum : 1.0;
  if (partly) {
    // No point of the open part found: nothing is known yet, so nothing is moved.
    fmean = openRays > 0 ? openF / openRays : 0.0;
    if (openRays == 0) V = 0.0;
  }
  l.coef = static_cast<float>(fmean * V);
  // The bound is the unoccluded transfer: a link whose few rays were all blocked may still be
  // partly visible, so it must be refined (or found small) rather than dropped.
  l.bound = static_cast<float>(fmean);
  // Any blocked ray, or a point that found no open spot: visibility is uncertain.
  double vspread = nvis < n || (partly && openRays < K) ? 1.0 : 0.0;
  l.spread = fmean > 0.0 ? static_cast<float>((hi - lo) / std::max(fmean, 1e-300) + vspread) : 0.0f;
  l.geom = 0.0f;
  return {n, n, nvis};
}

RayCount evaluateClusterLink(const SolverState& s, Link& l, Rng& rr, Rng& rs, double dist, int K) {
  K = std::clamp(K, 1, kMaxRays);
  Vec3 from[kMaxRays], to[kMaxRays], nf[kMaxRays], nt[kMaxRays];
  bool blocked[kMaxRays];
  for (int k = 0; k < K; ++k) from[k] = to[k] = Vec3(0.0);  // (quiets GCC's maybe-uninitialized)
  // A cluster at one end: point kernel between centres, visible fraction from K rays between
  // area-sampled surface points. Only pairs whose surfaces face each other count, each weighted by
  // the point kernel: a box's faces turned away from the sender see it through the box itself, and
  // counting them as blocked starved the faces that do see it (a room lost 2 % of its power).
  bool hidden[kMaxRays], underCover[kMaxRays];
  for (int k = 0; k < K; ++k) {
    std::uint32_t pf = kNone, pt = kNone;
    Vec3 x = s.pointOn(l.receiver, (k + rr.uniform()) / K, rr.uniform(), rr, nf[k], &pf);
    Vec3 y = s.pointOn(l.sender, (k + rs.uniform()) / K, rs.uniform(), rs, nt[k], &pt);
    // As for element links: a receiver point under a coplanar patch does not count (light arrives
    // only at the open part), a sender point there is blocked.
    underCover[k] = s.vis.coverOf(pf, x) != kNone;
    hidden[k] = s.vis.coverOf(pt, y) != kNone;
    liftPair(s, x, nf[k], y, nt[k], from[k], to[k]);
  }
  s.vis.occluded(from, to, K, blocked);
  if (s.opt.testOnlyUnblockedShadowRays) std::fill(blocked, blocked + K, false);  // (test only: SolverOptions)
  for (int k = 0; k < K; ++k) blocked[k] = blocked[k] || hidden[k];
  // The link moves light as the sender's intensity toward the receiver over the squared distance
  // between centroids, with the cosines of the centre direction: a far-field model whose error the
  // oracle bounds by ((r_s + r_r) / d)^2 of the link's power (refine.cpp). (Correcting it by the ratio
  // of the true to the modelled kernel over the link's few ray pairs was tried: a ratio of noisy
  // sums is biased, and the Soda Shoppe's balance went from 4.9 % to 10 %.)
  const Vec3 w = Vec3(l.dir);
  const double rs2 = s.h.radius(l.sender), rr2 = s.h.radius(l.receiver);
  const double d2 = std::max(dist * dist, 1e-12 * (rs2 + rr2) * (rs2 + rr2));
  int visible = 0, facing = 0;
  double wsum = 0.0, vsum = 0.0;
  for (int k = 0; k < K; ++k) {
    double wk = pointKernel(from[k], nf[k], to[k], nt[k]);
    if (wk <= 0.0 || underCover[k]) continue;
    ++facing;
    wsum += wk;
    vsum += blocked[k] ? 0.0 : wk;
    visible += blocked[k] ? 0 : 1;
  }
  const double V = wsum > 0.0 ? vsum / wsum : 1.0;
  double cosR = l.receiver.isCluster() ? 1.0 : std::max(0.0, glm::dot(s.h.element(l.receiver.index()).normal, w));
  // The mean of 1 / r^2 over the two nodes' points exceeds 1 / d^2 between centroids by
  // (s_s^2 + s_r^2) / (3 d^2) to second order (s^2: each node's mean squared spread about its
  // centroid, isotropic): the far-field model's leading bias, removed here.
  double g = (1.0 + (s.h.spread2(l.sender) + s.h.spread2(l.receiver)) / (3.0 * d2)) / d2;  // unoccluded; V applies to coef only
  if (l.sender.isCluster()) {
    l.coef = static_cast<float>(V * g * cosR);
    l.bound = static_cast<float>(g);
  } else {
    const Element& se = s.h.element(l.sender.index());
    double cosS = std::max(0.0, -glm::dot(se.normal, w));
    l.coef = static_cast<float>(V * g * cosR * cosS * se.area / kPi);
    l.bound = static_cast<float>(g * se.area / kPi);
  }
  l.spread = visible < facing || facing == 0 ? 1.0f : 0.0f;
  l.geom = static_cast<float>(dist > 0.0 ? (rs2 + rr2) / dist : 1e30);
  return {K, facing, visible};
}

RayCount trace(const SolverState& s, Link& l, double dist, int K, bool again) {
  // Receiver points: the same for all of a receiver's links (another set for traces again).
  Rng rr(s.opt.seed, l.receiver.value, again ? 0x5ED : 0x5EC);
  Rng rs(s.opt.seed, l.sender.value, l.receiver.value ^ (again ? 0x80000000u : 0u));
  if (!l.sender.isCluster() && !l.receiver.isCluster()) return evaluateElementLink(s, l, rr, rs, K);
  return evaluateClusterLink(s, l, rr, rs, dist, K);
}

}  // namespace

int evaluateLink(const SolverState& s, Link& l, bool again) {
  Vec3 d = s.h.center(l.sender) - s.h.center(l.receiver);
  double dist = glm::length(d);
  l.dir = glm::vec3(dist > 0.0 ? d / dist : Vec3(0, 0, 1));
  l.evaluated = true;
  int K = std::clamp(s.opt.raysPerLink, 1, kMaxRays);
  // A receiver partly under a coplanar cover: its form factor is the mean of exact point form
  // factors at its rays' open points (evaluateElementLink), so it takes enough of them for that mean
  // to settle near a contact. Few links have such receivers.
  if (!l.receiver.isCluster() && s.open[l.receiver.index()] < 1.0f && s.open[l.receiver.index()] > 0.0f)
    K = std::max(K, kCoverRays);
  // Direct light: an emitter's links carry most of a scene's power and cast its sharpest shadows.
  // The oracle keeps a link whose rays agree, and at 4 rays agreement says little: penumbra links
  // whose rays all happened to see the lamp were kept at full visibility, and the Cornell box's
  // short block and the floor's shadowed crease before it came out 1.8 % bright (0.8 % at 32 rays,
  // for 39 % more rays in all). Few links start at an emitter. A cluster of emitters (a lamp of
  // many patches) sends the same light: at 4 rays its shadows on three lights' floor (each disk 16
  // patches) were most of shooting's seed-to-seed noise there (1.13 % of the image; 0.66 % at 32).
  if (!l.receiver.isCluster() && s.emits(l.sender)) K = std::max(K, kEmitterRays);
  // Traced again: the oracle keeps reading the first trace's visibility (Link::seenVisible).
  const float firstSpread = l.spread, firstSigma = l.vsigma;
  RayCount rc = trace(s, l, dist, K, again);
  int rays = rc.traced;
  // Partly visible links: the visible fraction from K rays has a standard error of about
  // sqrt(V (1 - V) / K), and on the few large links of a coarse solution that noise is an energy
  // error (4 rays per link left the Cornell box 5 % out at eps 1; 256 rays, under 1 %). So a link
  // whose visibility error could move more than kVisibilityTolerance of the emitted power is traced
  // again with as many rays as that takes, up to kMaxRays; what is still too uncertain the refiner
  // splits whatever the threshold (refine.cpp).
  // Half a count added on either side: K rays that all agree do not prove the link fully visible or
  // fully blocked, and treating only one of the two as uncertain biased coarse solutions.
  auto sigma = [](const RayCount& c) {
    if (c.facing == 0) return 0.0;
    double v = (c.visible + 0.5) / (c.facing + 1.0);
    return std::sqrt(v * (1.0 - v) / c.facing);
  };
  double sig = sigma(rc);
  if (sig > 0.0 && K < kMaxRays) {
    double power = unoccludedPower(s, l);
    double need = std::ceil(double(K) * std::pow(sig * power / visibilityTolerance(s), 2.0));
    if (need > K) {
      K = static_cast<int>(std::min<double>(kMaxRays, need));
      rc = trace(s, l, dist, K, again);
      rays += rc.traced;
      sig = sigma(rc);
    }
  }
  l.vsigma = static_cast<float>(sig);
  if (again) {
    l.spread = firstSpread, l.vsigma = firstSigma;
  } else {
    const double V = l.bound > 0.0f ? double(l.coef) / double(l.bound) : 1.0;
    l.seenVisible = static_cast<std::uint8_t>(V >= 1.0 ? kSeenScale : std::clamp<long>(std::lround(V * kSeenScale), 0, kSeenScale - 1));
  }
  return rays;
}

/// Rays per overlapping link: the measured fraction's standard error is at most 0.5 / sqrt(K) of the
/// sender's power, itself under the threshold when the link is kept, and unbiased.
constexpr int kOverlapRays = 64;

/// Whether point x of a convex polygon's plane lies inside it (edges within a relative 1e-9), for
/// either winding.
bool insideConvex(const Polygon& poly, const Vec3& x) {
  const Vec3 normal = poly.areaVector();
  const double tol = 1e-9 * poly.radius() * poly.radius() * glm::length(normal);
  for (int k = 0; k < poly.n; ++k) {
    const Vec3& a = poly.v[k];
    const Vec3& b = poly.v[(k + 1) % poly.n];
    if (glm::dot(glm::cross(b - a, x - a), normal) < -tol) return false;
  }
  return true;
}

int measureOverlap(const SolverState& s, Link& l) {
  // A far-field link (transfer over the squared distance between centres) whose nodes overlap means
  // nothing: the sender may lie inside its receiver cluster, whose centre may be behind it (no light
  // at all) or 5 m away in another room (1/25 of it). The oracle keeps such a link only when all its
  // sender sends is below the threshold (refine.cpp, powerError), but the error is one-signed: in a
  // shooting pass every dim patch shoots through one link to the root cluster, and two rooms with a
  // sphere each lost 26 % of the spheres' light (1.6 % of the emitted power; the Soda Shoppe most of
  // its 2.7 %). So the link carries what rays find: the fraction F of the sender's cosine-distributed
  // rays that reach the front of a patch in the cluster, F A_s times the sender's radiosity, spread
  // over the cluster as any cluster link spreads its light (E_perp max(0, n.w), push_pull.cpp): its
  // placement stays the oracle's, under the threshold; its power is now right up to the rays' noise.
  // A cluster sender overlapping its receiver is the same far-field model at its worst, and the
  // oracle splits such a link unless all the cluster sends is under the threshold; but a memory
  // budget may keep it against the oracle (capRound), and then 1 / d^2 between centres 1 m apart
  // for clusters 1.5 m in radius handed the cluster of a room's floor 1.75 times the power of the
  // ceiling's, and a small glossy room under a tight budget created 7-10 % of its light. Such a link
  // carries F times the cluster's power the same way (SolverState::hostValue), F from rays leaving
  // its patches in proportion to their power when measured (their area while all are dark),
  // measured again at every refinement pass that keeps it so, since what its patches send changes.
  // An element receiver inside the sender's sphere (a ceiling and the cluster of the room under
  // it) takes F of the cluster's power over its open area.
  l.measured = true;
  const Vec3 w = glm::normalize(Vec3(l.dir));
  double projected = 0.0;  // sum of A max(0, n.w) over the cluster's patches: E_perp to power
  if (l.receiver.isCluster()) {
    const Cluster& c = s.h.cluster(l.receiver.index());
    for (std::uint32_t i = c.patchBegin; i < c.patchEnd; ++i) {
      // Over open areas: light reaches a patch partly under a coplanar cover only there.
      const std::uint32_t q = s.h.patchOrder()[i];  // the root element of patch q has index q
      projected += s.openArea(q) * std::max(0.0, glm::dot(s.h.patches()[q].normal, w));
    }
  } else {
    projected = s.openArea(l.receiver.index());  // irradiance over the open part, as any link's
  }
  // Whether a ray that hit the front of a patch reached the receiver.
  auto reaches = [&](const Vec3& o, const Vec3& d, const SurfaceHit& hit) {
    if (l.receiver.isCluster()) {
      const Cluster& c = s.h.cluster(l.receiver.index());
      const std::uint32_t at = s.patchPos[hit.patch];
      return at >= c.patchBegin && at < c.patchEnd;
    }
    const Element& re = s.h.element(l.receiver.index());
    return hit.patch == re.patch && insideConvex(re.poly, o + hit.t * d);
  };
  Rng rng(s.opt.seed ^ 0x0E7A9ull, l.sender.value, l.receiver.value);
  // Where rays leave: the element, or the sender cluster's patches by power (cumulative weights).
  std::vector<std::uint32_t> from;
  std::vector<double> cdf;
  if (l.sender.isCluster()) {
    const Cluster& sc = s.h.cluster(l.sender.index());
    double sum = 0.0, area = 0.0;
    for (std::uint32_t i = sc.patchBegin; i < sc.patchEnd; ++i) sum += luminance(s.B[s.h.patchOrder()[i]]) * s.openArea(s.h.patchOrder()[i]);
    for (std::uint32_t i = sc.patchBegin; i < sc.patchEnd; ++i) {
      const std::uint32_t q = s.h.patchOrder()[i];
      const double wq = sum > 0.0 ? luminance(s.B[q]) * s.openArea(q) : s.openArea(q);
      if (!(wq > 0.0)) continue;
      from.push_back(q);
      cdf.push_back(area += wq);
    }
    if (from.empty()) {
      l.coef = 0.0f;
      return 0;
    }
  }
  const double shift = rng.uniform();
  int hits = 0;
  for (int k = 0; k < kOverlapRays; ++k) {
    std::uint32_t patch;
    Vec3 o, n;
    if (l.sender.isCluster()) {
      const double x = rng.uniform() * cdf.back();
      const std::size_t j = std::min<std::size_t>(std::size_t(std::upper_bound(cdf.begin(), cdf.end(), x) - cdf.begin()), from.size() - 1);
      patch = from[j];
      n = s.h.patches()[patch].normal;
      o = s.h.patches()[patch].poly.sample(rng.uniform(), rng.uniform());
    } else {
      const Element& se = s.h.element(l.sender.index());
      patch = se.patch, n = se.normal;
      o = se.poly.sample(rng.uniform(), rng.uniform());
    }
    Vec3 u, v;
    audit::tangentFrame(n, u, v);
    const Vec3 d = audit::latticeCosineDirection(n, u, v, shift, k, kOverlapRays, rng.uniform());
    if (s.vis.coverOf(patch, o) != kNone) continue;  // under a coplanar patch: nothing leaves
    const SurfaceHit hit = s.vis.intersectFrom(o, d, patch);
    if (!hit.hit || glm::dot(s.h.patches()[hit.patch].normal, d) >= 0.0) continue;
    hits += reaches(o, d, hit) ? 1 : 0;
  }
  const double F = double(hits) / kOverlapRays;
  // The sender's quantity on a measured link: radiosity for an element (F A_s of it arrives), and
  // for a cluster its power over 4 pi (SolverState::hostValue; 4 pi F of it arrives).
  const double per = l.sender.isCluster() ? 4.0 * kPi : s.h.element(l.sender.index()).area;
  l.coef = projected > 0.0 ? static_cast<float>(F * per / projected) : 0.0f;
  return kOverlapRays;
}

double catchingArea(const SolverState& s, const Link& l) {
  // A cluster catches light with its projected area, on average a quarter of its surface area
  // (Cauchy's formula for convex bodies; an estimate for the rest).
  // An element catches it with its open part only (SolverState::open).
  return l.receiver.isCluster() ? 0.25 * s.h.area(l.receiver) : s.openArea(l.receiver.index());
}

double unoccludedPower(const SolverState& s, const Link& l) {
  return catchingArea(s, l) * luminance(s.senderValue(l)) * double(l.bound);
}

}  // namespace hr::detail
