// The independent energy audit: absorbed and escaped power measured without the links. Fronts absorb
// A (1 - rho_d) E, less what an extension sends on from there (its reflected power); escaped light is
// found by rays: cosine-distributed for the Lambertian part, drawn by the extension for its own. Surfaces are one-sided: light that reaches a back face (the top of a ceiling light
// panel, the outside of a box seen through a gap) is absorbed there, a black back, and is found with
// the escaped power by cosine-distributed rays from every leaf. Without it a thin light under a
// ceiling lost 1-2 % of the emitted power from the balance. The estimators (ray budget, lattice
// directions, variances, totals) are shared with the VISION-like host: hr/audit_estimators.h.
#include <hr/audit_estimators.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "solver_state.h"

namespace hr::detail {
namespace {

using audit::LeafAudit;

/// Where a ray leaving leaf e at o in direction d ends (audit::Fate); an origin under a coplanar
/// patch is caught by that patch's back.
int fate(const SolverState& s, const Element& e, const Vec3& o, const Vec3& d) {
  if (s.vis.coverOf(e.patch, o) != kNone) return audit::kBack;
  SurfaceHit hit = s.vis.intersectFrom(o, d, e.patch);
  if (!hit.hit) return audit::kEscaped;
  return glm::dot(s.h.patches()[hit.patch].normal, d) > 0.0 ? audit::kBack : audit::kFront;
}

/// The leaf's Lambertian light: cosine-distributed rays.
void auditLambertian(const SolverState& s, std::uint32_t i, double sent, LeafAudit& a) {
  const Element& e = s.h.element(i);
  // Radiosity is the open part's (SolverState::open): what leaves is traced from there, and a
  // covered part's emission stays under its cover, absorbed by the cover's back.
  const double f = s.open[i];
  const Rgb P = s.B[i] * s.openArea(i);  // W leaving the leaf
  a.back += s.emitted(i) * (e.area * (1.0 - f));
  if (maxComponent(P) <= 0.0) return;
  const int M = audit::raysFor(luminance(P), sent);
  a.rays += std::uint64_t(M);
  Rng rng(s.opt.seed ^ audit::kLambertianSeed, i);
  Vec3 u, v;
  audit::tangentFrame(e.normal, u, v);
  int count[3] = {0, 0, 0}, fromOpen = 0;
  const double shift = rng.uniform();
  for (int k = 0; k < M; ++k) {
    Vec3 o = e.poly.sample(rng.uniform(), rng.uniform());
    Vec3 d = audit::latticeCosineDirection(e.normal, u, v, shift, k, M, rng.uniform());
    if (f < 1.0 && s.vis.coverOf(e.patch, o) != kNone) continue;  // P leaves from the open part
    ++count[fate(s, e, o, d)];
    ++fromOpen;
  }
  if (fromOpen == 0) {
    a.back += P;  // no ray found the open part: too small to tell where its light goes
    return;
  }
  const double weight[3] = {double(count[0]), double(count[1]), double(count[2])};
  audit::addLambertian(a, P, weight, double(fromOpen));
}

/// The extension's light at a simulated leaf: directions it samples itself, each standing for a
/// share of its power; the variance from the spread of those shares.
void auditExtension(const SolverState& s, std::uint32_t i, double sent, LeafAudit& a) {
  const Element& e = s.h.element(i);
  const NodeId leaf{i};
  const Rgb P = s.ext->reflectedPower(leaf);
  if (maxComponent(P) <= 0.0) return;
  const int M = audit::raysFor(luminance(P), sent);
  a.rays += std::uint64_t(M);
  Rng rng(s.opt.seed ^ audit::kExtensionSeed, i);
  Rgb sum[3] = {Rgb(0.0), Rgb(0.0), Rgb(0.0)}, sum2[3] = {Rgb(0.0), Rgb(0.0), Rgb(0.0)};
  for (int k = 0; k < M; ++k) {
    Vec3 o = e.poly.sample(rng.uniform(), rng.uniform()), d(0.0);
    Rgb w = s.ext->sampleExitant(leaf, (k + rng.uniform()) / M, rng.uniform(), d);
    if (!allFinite(w) || maxComponent(w) <= 0.0 || glm::dot(d, d) <= 0.0) continue;
    int f = fate(s, e, o, glm::normalize(d));
    sum[f] += w, sum2[f] += w * w;
  }
  audit::addDrawn(a, sum, sum2, double(M));
}

LeafAudit auditLeaf(const SolverState& s, std::uint32_t i, double sent) {
  LeafAudit a;
  // Absorbed: what arrived (at the open part), less what the Lambertian part and the extension send on.
  a.absorbed = s.openArea(i) * (Rgb(1.0) - s.mat(i).diffuse) * s.Et[i];
  auditLambertian(s, i, sent, a);
  if (s.ext && s.owned[i]) {
    a.absorbed -= s.ext->reflectedPower(NodeId{i});
    auditExtension(s, i, sent, a);
  }
  return a;
}

}  // namespace

audit::Totals auditEnergy(SolverState& s) {
  PhaseTimer t(s.clkEnergy);
  const auto& els = s.h.elements();
  double sent = 0.0;
  for (std::size_t i = 0; i < els.size(); ++i) {
    if (!els[i].leaf()) continue;
    sent += luminance(s.B[i]) * s.openArea(static_cast<std::uint32_t>(i));
    if (s.ext && s.owned[i]) sent += luminance(s.ext->reflectedPower(NodeId{static_cast<std::uint32_t>(i)}));
  }
  std::vector<LeafAudit> per(els.size());
  // A few leaves hold most of the rays (rays follow power: a lamp's leaves, first in element order),
  // and the automatic partitioner handed them to one thread as one piece (three lights' audit ran
  // 1.14 times in parallel on two threads), so the range is split down to 16 elements a task. Each
  // leaf's rays and sum are its own: the same bits either way.
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, els.size(), 16),
      [&](const auto& r) {
        s.clkEnergy.sawThread();
        for (std::size_t i = r.begin(); i != r.end(); ++i)
          if (els[i].leaf()) per[i] = auditLeaf(s, static_cast<std::uint32_t>(i), sent);
      },
      tbb::simple_partitioner());
  // Summed in element order: the totals do not depend on the thread count.
  audit::Totals res = audit::sum(per);
  s.rays += res.rays;
  return res;
}

}  // namespace hr::detail
