// The energy audit, measured without the interactions: a leaf absorbs A (1 - rho_d) E of all it
// received; the light it sends is followed by cosine-distributed rays from points of the curved
// surface (its own normal at each) against the exact surfaces: rays that leave the scene escaped,
// rays that meet a surface's back were absorbed by a black back. Rays are shared among the leaves in
// proportion to their power (about 5e5 in all), so the audit's standard error stays near 0.07 % of
// what the leaves send whatever their count.
#include <hr/rng.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "state.h"

namespace vision::detail {
namespace {

constexpr double kRayBudget = 1 << 19;

struct LeafAudit {
  Rgb absorbed{0.0}, escaped{0.0}, back{0.0}, var{0.0};
  std::uint64_t rays = 0;
};

void auditLeaf(const State& s, const Element& e, std::uint64_t key, double sent, LeafAudit& a) {
  const Surface& sf = s.h.surfaces()[e.surface];
  a.absorbed = e.g.area * (Rgb(1.0) - s.material(e).diffuse) * e.Etot;
  const Rgb P = e.B * e.g.area;
  if (hr::maxComponent(P) <= 0.0) return;
  const double share = sent > 0.0 ? hr::luminance(P) / sent : 0.0;
  const int M = std::max(1, int(std::min(1e6, std::ceil(share * kRayBudget))));
  a.rays += std::uint64_t(M);
  hr::Rng rng(s.opt.seed ^ 0xE5CA9Eull, key);
  const double shift = rng.uniform();
  constexpr double kGolden = 0.6180339887498949;
  double count[3] = {0, 0, 0}, wsum = 0.0;
  const double jmean = sf.jacobian(0.5 * (e.rect.u0 + e.rect.u1), 0.5 * (e.rect.v0 + e.rect.v1));
  for (int k = 0; k < M; ++k) {
    // A point uniform in parameter space, weighted by its area element (most maps are equal-area).
    double u = e.rect.u0 + rng.uniform() * e.rect.du(), v = e.rect.v0 + rng.uniform() * e.rect.dv();
    Vec3 o = sf.point(u, v), n = sf.normal(u, v);
    double w = jmean > 0.0 ? sf.jacobian(u, v) / jmean : 1.0;
    Vec3 t = std::abs(n.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
    Vec3 tu = glm::normalize(glm::cross(t, n)), tv = glm::cross(n, tu);
    // Cosine-distributed directions from a shifted rank-1 lattice (stratified, unbiased).
    double phi = 2.0 * hr::kPi * std::fmod(shift + k * kGolden, 1.0), r = std::sqrt((k + rng.uniform()) / M);
    Vec3 d = r * std::cos(phi) * tu + r * std::sin(phi) * tv + std::sqrt(std::max(0.0, 1.0 - r * r)) * n;
    CurvedHit h = s.vis.intersect(o + n * s.vis.epsilon(), d);
    count[!h.hit ? 0 : h.front ? 2 : 1] += w;
    wsum += w;
  }
  a.escaped = P * (count[0] / wsum);
  a.back = P * (count[1] / wsum);
  auto var = [&](double m) { return (m + 0.5) * (wsum - m + 0.5) / ((wsum + 1.0) * (wsum + 1.0) * wsum); };
  a.var = P * P * (var(count[0]) + var(count[1]));
}

}  // namespace

Audit auditEnergy(const State& s) {
  // The leaves in a fixed order (surface, then depth first): sums independent of the threads.
  std::vector<const Element*> leaves;
  for (const Element& r : s.h.roots())
    forEachElement(r, [&](const Element& e) {
      if (e.leaf()) leaves.push_back(&e);
    });
  double sent = 0.0;
  for (const Element* e : leaves) sent += hr::luminance(e->B) * e->g.area;
  std::vector<LeafAudit> per(leaves.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 64), [&](const auto& r) {
    sawThread(s.auditThreads);
    for (std::size_t i = r.begin(); i != r.end(); ++i) auditLeaf(s, *leaves[i], i, sent, per[i]);
  });
  Audit res;
  Rgb var(0.0);
  for (const LeafAudit& a : per) {
    res.escaped += a.escaped;
    res.back += a.back;
    res.absorbed += a.absorbed + a.back;
    var += a.var;
    res.rays += a.rays;
  }
  res.stdErr = glm::sqrt(var);
  s.rays += res.rays;
  return res;
}

}  // namespace vision::detail
