// The estimate of one accepted interaction. Between two elements: the unoccluded form factor
// averaged over the receiver by Gauss-Legendre points, each point's form factor by the contour
// integral over the sender's outline (exact for flat senders; for curved ones while every sample
// of the sender faces the point above its horizon, else split until each piece does or does not
// face it, contour.cpp), times the visible fraction; the same points give the mean over each quarter
// of the receiver, where the light falls within it (shoot.cpp). With a cluster at either end: the
// sender's unshot intensity over the squared distance between centroids (spreads corrected), the
// receiver's cosine averaged over it. Visibility: shadow rays between points of the two nodes,
// weighted by the point kernel, more rays while the visible fraction is uncertain by more than the
// tolerance allows.
#include <hr/rng.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <optional>

#include "state.h"

namespace vision::detail {
namespace {

constexpr double kGauss5[5] = {0.0469100770306680, 0.2307653449471585, 0.5, 0.7692346550528415, 0.9530899229693320};
constexpr double kWeight5[5] = {0.1184634425280945, 0.2393143352496832, 0.2844444444444444, 0.2393143352496832, 0.1184634425280945};
constexpr double kGauss3[3] = {0.1127016653792583, 0.5, 0.8872983346207417};
constexpr double kWeight3[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
constexpr int kMaxRays = 256;

std::uint64_t keyOf(std::uint32_t owner, const Rect& r) {
  std::uint64_t k = hr::mix64(owner);
  for (double v : {r.u0, r.u1, r.v0, r.v1}) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    k = hr::mix64(k ^ bits);
  }
  return k;
}
std::uint64_t keyOf(const Sender& s) { return s.cluster != hr::kNone ? hr::mix64(~std::uint64_t(s.cluster)) : keyOf(s.e->surface, s.rect); }
std::uint64_t keyOf(const Receiver& r) { return r.cluster != hr::kNone ? hr::mix64(~std::uint64_t(r.cluster)) : keyOf(r.e->surface, r.e->rect); }

class PointToSender {
 public:
  PointToSender(const State& s, const Sender& snd) : sf_(s.h.surfaces()[snd.e->surface]), rect_(snd.rect) {
    outline(sf_, rect_, pts_);
    if (sf_.planar()) return;
    curved_.emplace(sf_, rect_);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double u = rect_.u0 + kGauss3[i] * rect_.du(), v = rect_.v0 + kGauss3[j] * rect_.dv();
        inner_.push_back(sf_.point(u, v));
        innerN_.push_back(sf_.normal(u, v));
      }
  }
  double operator()(const Vec3& x, const Vec3& n) const {
    if (sf_.planar()) {
      if (glm::dot(sf_.normal(0.5, 0.5), x - pts_[0]) <= 0.0) return 0.0;  // behind a one-sided sender
      return contourFormFactor(x, n, pts_, true);
    }
    // The contour integral holds while the sender faces x everywhere and lies above x's horizon.
    const double tol = 1e-12 * (1.0 + glm::length(x));
    auto faces = [&](const Vec3& y, const Vec3& ny) { return glm::dot(ny, x - y) >= -tol && glm::dot(n, y - x) >= -tol; };
    bool ok = true;
    for (std::size_t k = 0; ok && k < pts_.size(); ++k) ok = glm::dot(n, pts_[k] - x) >= -tol;
    for (std::size_t k = 0; ok && k < inner_.size(); ++k) ok = faces(inner_[k], innerN_[k]);
    if (ok) ok = outlineFaces(x, tol);
    return ok ? contourFormFactor(x, n, pts_, false) : curved_->formFactor(x, n);
  }

 private:
  /// The outline's own points face x too (their normals from the parameter values of the corners
  /// and edge midpoints, the probes; enough for elements whose cone of normals is narrow).
  bool outlineFaces(const Vec3& x, double tol) const { return curved_->topFaces(x, tol); }
  const Surface& sf_;
  Rect rect_;
  mutable std::optional<CurvedPieces> curved_;  // curved senders: probes and pieces, made as needed
  std::vector<Vec3> pts_, inner_, innerN_;
};

/// A point on a node and its normal, drawn from (a, b) in [0, 1)^2; returns its area weight
/// (the Jacobian against its mean, so that weighted points are uniform in area).
double pointOn(const State& s, std::uint32_t cluster, const Element* e, const Rect& rect, double a, double b, hr::Rng& rng,
               Vec3& p, Vec3& n) {
  const Surface* sf;
  Rect r = rect;
  if (cluster != hr::kNone) {
    const std::uint32_t lo = s.first[cluster], hi = lo + s.h.clusters()[cluster].surfaceCount;
    double target = s.areaPrefix[lo] + a * (s.areaPrefix[hi] - s.areaPrefix[lo]);
    auto it = std::upper_bound(s.areaPrefix.begin() + lo, s.areaPrefix.begin() + hi + 1, target);
    std::size_t i = std::clamp<std::size_t>(std::size_t(it - s.areaPrefix.begin()) - 1, lo, hi - 1);
    sf = &s.h.surfaces()[s.order[i]];
    r = Rect{};
    a = rng.uniform();
  } else {
    sf = &s.h.surfaces()[e->surface];
  }
  double u = r.u0 + a * r.du(), v = r.v0 + b * r.dv();
  p = sf->point(u, v), n = sf->normal(u, v);
  if (sf->kind != SurfaceKind::Bilinear) return 1.0;
  double mean = 0.25 * (sf->jacobian(r.u0, r.v0) + sf->jacobian(r.u1, r.v0) + sf->jacobian(r.u1, r.v1) + sf->jacobian(r.u0, r.v1));
  return mean > 0.0 ? sf->jacobian(u, v) / mean : 1.0;
}

struct RayCount {
  int facing = 0, visible = 0;
  double V = 1.0;
};

RayCount traceRays(const State& s, const Sender& snd, const Receiver& rc, int K) {
  hr::Rng rr(s.opt.seed, keyOf(rc), 0x5EC), rs(s.opt.seed, keyOf(snd), keyOf(rc));
  Vec3 from[kMaxRays], to[kMaxRays];
  double w[kMaxRays];
  bool blocked[kMaxRays];
  int n = 0;
  const double eps = s.vis.epsilon();
  for (int k = 0; k < K; ++k) {
    Vec3 x, nx, y, ny;
    double wx = pointOn(s, rc.cluster, rc.e, rc.e ? rc.e->rect : Rect{}, (k + rr.uniform()) / K, rr.uniform(), rr, x, nx);
    double wy = pointOn(s, snd.cluster, snd.e, snd.rect, (k + rs.uniform()) / K, rs.uniform(), rs, y, ny);
    Vec3 d = y - x;
    double r2 = glm::dot(d, d), cx = glm::dot(nx, d), cy = -glm::dot(ny, d);
    if (!(cx > 0.0 && cy > 0.0 && r2 > 0.0)) continue;
    // Ends lifted off their surfaces, by at most a quarter of their height above the other's plane.
    from[n] = x + nx * std::min(eps, 0.25 * glm::dot(nx, d));
    to[n] = y + ny * std::min(eps, 0.25 * cy);
    w[n++] = wx * wy * cx * cy / (r2 * r2);
  }
  auto t0 = std::chrono::steady_clock::now();
  s.vis.occluded(from, to, n, blocked);
  s.visibilityNs += std::uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count());
  s.rays += std::uint64_t(n);
  RayCount rc2;
  double wsum = 0.0, vsum = 0.0;
  for (int k = 0; k < n; ++k) {
    ++rc2.facing;
    wsum += w[k];
    if (!blocked[k]) vsum += w[k], ++rc2.visible;
  }
  rc2.V = wsum > 0.0 ? vsum / wsum : 1.0;
  return rc2;
}

double sigmaOf(const RayCount& c) {
  if (c.facing == 0) return 0.0;
  double v = (c.visible + 0.5) / (c.facing + 1.0);  // half a count each way: agreeing rays prove nothing
  return std::sqrt(v * (1.0 - v) / c.facing);
}

}  // namespace

namespace {

/// The receiver's quadrature grid of m x m points (m 3 or 5), from the cache when there is one.
const ReceiverPoints::Grid& gridOf(const Surface& rs, const Rect& r, int m, ReceiverPoints* cache, ReceiverPoints::Grid& local) {
  ReceiverPoints::Grid& g = cache ? cache->grid[m == 5 ? 1 : 0] : local;
  if (g.made) return g;
  const double* node = m == 5 ? kGauss5 : kGauss3;
  const double* wt = m == 5 ? kWeight5 : kWeight3;
  g.p.clear(), g.n.clear(), g.w.clear();
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = r.u0 + node[i] * r.du(), v = r.v0 + node[j] * r.dv();
      g.w.push_back(wt[i] * wt[j] * rs.jacobian(u, v));
      g.p.push_back(rs.point(u, v));
      g.n.push_back(rs.normal(u, v));
    }
  g.made = true;
  return g;
}

}  // namespace

Estimate estimate(const State& s, const Sender& snd, const Receiver& rc, ReceiverPoints* points) {
  const Geometry& rg = rc.g(s.h);
  Estimate est;
  Vec3 d = snd.g.center - rg.center;
  const double dist = glm::length(d);
  est.toSender = dist > 0.0 ? d / dist : rg.coneAxis;
  est.distance = dist;
  // A sender whose normals cancel (a whole sphere) is taken as a cluster is: seen square on.
  const double cosS = snd.cluster == hr::kNone && snd.g.normal != Vec3(0.0) ? glm::dot(snd.g.normal, est.toSender) : 1.0;
  est.radius = hr::senderDiskRadius(snd.g.spread2, cosS);
  if (snd.cluster == hr::kNone && s.h.surfaces()[snd.e->surface].planar())
    est.senderNormal = glm::vec3(snd.g.coneAxis), est.senderShape = snd.g.shape;
  Rgb Eun(0.0);
  double catching = rg.area;
  if (snd.cluster == hr::kNone && rc.e) {
    // Element to element: receiver points by Gauss-Legendre, each with the contour form factor.
    const Surface& rs = s.h.surfaces()[rc.e->surface];
    PointToSender F(s, snd);
    const bool self = snd.e->surface == rc.e->surface && rs.concave();
    const Rect& r = rc.e->rect;
    const bool near = dist <= 0.0 || (snd.g.radius + rg.radius) > 0.5 * dist;
    const int m = near ? 5 : 3;
    const double* node = near ? kGauss5 : kGauss3;
    ReceiverPoints::Grid local;
    const ReceiverPoints::Grid& grid = gridOf(rs, r, m, points, local);
    double fsum = 0.0, asum = 0.0, qf[4] = {0.0, 0.0, 0.0, 0.0}, qa[4] = {0.0, 0.0, 0.0, 0.0};
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) {
        double u = r.u0 + node[i] * r.du(), v = r.v0 + node[j] * r.dv();
        const double wq = grid.w[std::size_t(i * m + j)];
        const Vec3& x = grid.p[std::size_t(i * m + j)];
        const Vec3& xn = grid.n[std::size_t(i * m + j)];
        // A point of a concave surface inside the sender's own rectangle (an element lighting
        // itself or a part of itself) is enclosed by the sender's outline: see insideFormFactor.
        const bool inside = self && u > snd.rect.u0 && u < snd.rect.u1 && v > snd.rect.v0 && v < snd.rect.v1;
        const double f = inside ? insideFormFactor(rs, snd.rect, u, v, x, xn) : F(x, xn);
        fsum += wq * f;
        asum += wq;
        // Quarters of the receiver's parameter rectangle; a point on a mid-line counts half to each.
        for (int q = 0; q < 4; ++q) {
          const double su = 2 * i + 1 == m ? 0.5 : ((q & 1) == (2 * i >= m) ? 1.0 : 0.0);
          const double sv = 2 * j + 1 == m ? 0.5 : (((q >> 1) & 1) == (2 * j >= m) ? 1.0 : 0.0);
          qf[q] += su * sv * wq * f, qa[q] += su * sv * wq;
        }
      }
    const double ff = asum > 0.0 ? fsum / asum : 0.0;
    est.quarters = true;
    for (int q = 0; q < 4; ++q) est.quarterF[q] = qa[q] > 0.0 ? qf[q] / qa[q] : ff;
    Eun = snd.U * ff + extensionIrradiance(s, snd, *rc.e, ff);
  } else {
    // A cluster at one end: far field. The mean of 1/r^2 over both nodes exceeds 1/d^2 between
    // centroids by (s_s^2 + s_r^2) / (3 d^2) to second order.
    const double d2 = std::max(dist * dist, 1e-300);
    const double g = (1.0 + (snd.g.spread2 + rg.spread2) / (3.0 * d2)) / d2;
    Rgb Eperp = (unshotIntensity(s, snd, -est.toSender) + extensionIntensity(s, snd, -est.toSender)) * g;
    if (rc.e) {
      const Surface& rs = s.h.surfaces()[rc.e->surface];
      double c = 0.0, a = 0.0;
      const Rect& r = rc.e->rect;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double u = r.u0 + kGauss3[i] * r.du(), v = r.v0 + kGauss3[j] * r.dv();
          double wq = kWeight3[i] * kWeight3[j] * rs.jacobian(u, v);
          c += wq * std::max(0.0, glm::dot(rs.normal(u, v), est.toSender));
          a += wq;
        }
      Eun = Eperp * (a > 0.0 ? c / a : 0.0);
    } else {
      Eun = Eperp;
      catching = 0.25 * rg.area;  // a cluster's mean projected area (Cauchy, convex bodies)
    }
  }
  est.unoccluded = catching * hr::luminance(Eun);
  if (!(est.unoccluded > 0.0)) {
    est.E = Rgb(0.0);
    est.V = 0.0;
    return est;
  }
  if (snd.V >= 0.0) {
    // Handed down for where its light falls only: the visible fraction is the one traced above.
    est.V = snd.V;
    est.E = Eun * est.V;
    return est;
  }
  int K = std::clamp(s.opt.raysPerLink, 1, kMaxRays);
  RayCount c = traceRays(s, snd, rc, K);
  double sig = sigmaOf(c);
  if (sig * est.unoccluded > s.visTolerance && K < kMaxRays) {
    double need = std::ceil(K * std::pow(sig * est.unoccluded / s.visTolerance, 2.0));
    K = int(std::min<double>(kMaxRays, need));
    c = traceRays(s, snd, rc, K);
    sig = sigmaOf(c);
  }
  est.V = c.V;
  est.sigma = sig;
  est.mixed = c.visible > 0 && c.visible < c.facing;
  est.E = Eun * est.V;
  return est;
}

}  // namespace vision::detail
