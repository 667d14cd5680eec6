// The energy audit, measured without the interactions: a leaf absorbs A (1 - rho_d) E of all it
// received; the light it sends is followed by cosine-distributed rays from points of the curved
// surface (its own normal at each) against the exact surfaces: rays that leave the scene escaped,
// rays that meet a surface's back were absorbed by a black back. Rays are shared among the leaves in
// proportion to their power (about 5e5 in all), so the audit's standard error stays near 0.07 % of
// what the leaves send whatever their count. With an extension, a leaf it simulates absorbs less
// what the extension sends on (its reflected power), and that light is followed by directions the
// extension draws itself, each standing for a share of its power (as on the BRIGHT-like host). The
// estimators (ray budget, lattice directions, variances, totals) are the hosts' shared ones:
// hr/audit_estimators.h; the leaves, their points and the tracing against curved surfaces are this host's.
#include <hr/audit_estimators.h>
#include <hr/rng.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "state.h"

namespace vision::detail {
namespace {

using hr::audit::LeafAudit;

/// Where light leaving o along d ends (hr::audit::Fate).
int fate(const State& s, const Vec3& o, const Vec3& n, const Vec3& d) {
  CurvedHit h = s.vis.intersect(o + n * s.vis.epsilon(), d);
  return !h.hit ? hr::audit::kEscaped : h.front ? hr::audit::kFront : hr::audit::kBack;
}

/// The extension's light at a leaf: directions it draws, from points uniform in area.
void auditExtension(const State& s, const Element& e, std::uint64_t key, double sent, LeafAudit& a) {
  const Surface& sf = s.h.surfaces()[e.surface];
  const hr::NodeId leaf{e.id};
  const Rgb P = s.ext->reflectedPower(leaf);
  if (hr::maxComponent(P) <= 0.0) return;
  const int M = hr::audit::raysFor(hr::luminance(P), sent);
  a.rays += std::uint64_t(M);
  hr::Rng rng(s.opt.seed ^ hr::audit::kExtensionSeed, key);
  const double jmean = sf.jacobian(0.5 * (e.rect.u0 + e.rect.u1), 0.5 * (e.rect.v0 + e.rect.v1));
  Rgb sum[3] = {Rgb(0.0), Rgb(0.0), Rgb(0.0)}, sum2[3] = {Rgb(0.0), Rgb(0.0), Rgb(0.0)};
  double jsum = 0.0;  // points uniform in parameter space, weighted by their area element
  for (int k = 0; k < M; ++k) {
    double u = e.rect.u0 + rng.uniform() * e.rect.du(), v = e.rect.v0 + rng.uniform() * e.rect.dv();
    const double j = jmean > 0.0 ? sf.jacobian(u, v) / jmean : 1.0;
    jsum += j;
    Vec3 d(0.0);
    Rgb w = s.ext->sampleExitant(leaf, (k + rng.uniform()) / M, rng.uniform(), d);
    if (!hr::allFinite(w) || hr::maxComponent(w) <= 0.0 || glm::dot(d, d) <= 0.0) continue;
    int f = fate(s, sf.point(u, v), sf.normal(u, v), glm::normalize(d));
    sum[f] += j * w, sum2[f] += j * j * w * w;
  }
  if (!(jsum > 0.0)) return;
  hr::audit::addDrawn(a, sum, sum2, jsum);
}

void auditLeaf(const State& s, const Element& e, std::uint64_t key, double sent, LeafAudit& a) {
  const Surface& sf = s.h.surfaces()[e.surface];
  a.absorbed = e.g.area * (Rgb(1.0) - s.material(e).diffuse) * e.Etot;
  if (s.owned(e)) {
    a.absorbed -= s.ext->reflectedPower(hr::NodeId{e.id});
    auditExtension(s, e, key, sent, a);
  }
  const Rgb P = e.B * e.g.area;
  if (hr::maxComponent(P) <= 0.0) return;
  const int M = hr::audit::raysFor(hr::luminance(P), sent);
  a.rays += std::uint64_t(M);
  hr::Rng rng(s.opt.seed ^ hr::audit::kLambertianSeed, key);
  const double shift = rng.uniform();
  double count[3] = {0, 0, 0}, wsum = 0.0;
  const double jmean = sf.jacobian(0.5 * (e.rect.u0 + e.rect.u1), 0.5 * (e.rect.v0 + e.rect.v1));
  for (int k = 0; k < M; ++k) {
    // A point uniform in parameter space, weighted by its area element (most maps are equal-area).
    double u = e.rect.u0 + rng.uniform() * e.rect.du(), v = e.rect.v0 + rng.uniform() * e.rect.dv();
    Vec3 o = sf.point(u, v), n = sf.normal(u, v);
    double w = jmean > 0.0 ? sf.jacobian(u, v) / jmean : 1.0;
    Vec3 tu, tv;
    hr::audit::tangentFrame(n, tu, tv);
    Vec3 d = hr::audit::latticeCosineDirection(n, tu, tv, shift, k, M, rng.uniform());
    count[fate(s, o, n, d)] += w;
    wsum += w;
  }
  hr::audit::addLambertian(a, P, count, wsum);
}

}  // namespace

hr::audit::Totals auditEnergy(const State& s) {
  // The leaves in a fixed order (surface, then depth first): sums independent of the threads.
  std::vector<const Element*> leaves;
  for (const Element& r : s.h.roots())
    forEachElement(r, [&](const Element& e) {
      if (e.leaf()) leaves.push_back(&e);
    });
  double sent = 0.0;
  for (const Element* e : leaves) {
    sent += hr::luminance(e->B) * e->g.area;
    if (s.owned(*e)) sent += hr::luminance(s.ext->reflectedPower(hr::NodeId{e->id}));
  }
  std::vector<LeafAudit> per(leaves.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 64), [&](const auto& r) {
    hr::markThread(s.auditThreads);
    for (std::size_t i = r.begin(); i != r.end(); ++i) auditLeaf(s, *leaves[i], i, sent, per[i]);
  });
  hr::audit::Totals res = hr::audit::sum(per);
  s.rays += res.rays;
  return res;
}

}  // namespace vision::detail
