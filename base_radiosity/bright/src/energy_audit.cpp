// The independent energy audit: absorbed and escaped power measured without the links. Fronts absorb
// A (1 - rho_d) E, less what an extension sends on from there (its reflected power); escaped light is
// found by rays: cosine-distributed for the Lambertian part, drawn by the extension for its own. Surfaces are one-sided: light that reaches a back face (the top of a ceiling light
// panel, the outside of a box seen through a gap) is absorbed there, a black back, and is found with
// the escaped power by cosine-distributed rays from every leaf. Without it a thin light under a
// ceiling lost 1-2 % of the emitted power from the balance.
#include <tbb/parallel_for.h>

#include <cmath>

#include "solver_state.h"

namespace hr::detail {
namespace {

// Rays shared among the leaves in proportion to their power: the standard error of the escaped
// power is then at most about 1/(2 sqrt(budget)) = 0.07 % of the emitted power, whatever the leaf
// count (a fixed 64 rays per leaf spent 3.8 M rays on the Soda Shoppe's dark leaves).
constexpr double kRayBudget = 1 << 19;

struct LeafAudit {
  Rgb absorbed{0.0}, escaped{0.0}, back{0.0}, var{0.0};
  std::uint64_t rays = 0;
};

/// How many audit rays a leaf's power of luminance p gets (at least one).
int raysFor(double p, double sent) {
  const double share = sent > 0.0 ? p / sent : 0.0;
  return std::max(1, static_cast<int>(std::min(1e6, std::ceil(share * kRayBudget))));
}

/// Where a ray leaving leaf e at o in direction d ends: 0 escaped, 1 a black back (or the origin is
/// under a coplanar patch: caught by its back), 2 a front (absorbed or reflected there via links).
int fate(const SolverState& s, const Element& e, const Vec3& o, const Vec3& d) {
  if (s.vis.coverOf(e.patch, o) != kNone) return 1;
  SurfaceHit hit = s.vis.intersectFrom(o, d, e.patch);
  if (!hit.hit) return 0;
  return glm::dot(s.h.patches()[hit.patch].normal, d) > 0.0 ? 1 : 2;
}

/// The leaf's Lambertian light: cosine-distributed rays.
void auditLambertian(const SolverState& s, std::uint32_t i, double sent, LeafAudit& a) {
  const Element& e = s.h.element(i);
  const Rgb P = s.B[i] * e.area;  // W leaving the leaf
  if (maxComponent(P) <= 0.0) return;
  const int M = raysFor(luminance(P), sent);
  a.rays += std::uint64_t(M);
  Rng rng(s.opt.seed ^ 0xE5CA9Eull, i);
  Vec3 t = std::abs(e.normal.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  Vec3 u = glm::normalize(glm::cross(t, e.normal)), v = glm::cross(e.normal, u);
  int count[3] = {0, 0, 0};
  // Directions from a randomly shifted rank-1 lattice over (sin^2 theta, phi), cosine-weighted:
  // stratified for any ray count and unbiased (every ray is marginally uniform). A square grid
  // with sqrt(M) rounded left its outermost ring short whenever M was not a square: a 1 % bias.
  const double shift = rng.uniform();
  constexpr double kGolden = 0.6180339887498949;
  for (int k = 0; k < M; ++k) {
    Vec3 o = e.poly.sample(rng.uniform(), rng.uniform());
    double phi = 2.0 * kPi * std::fmod(shift + k * kGolden, 1.0), r = std::sqrt((k + rng.uniform()) / M);
    Vec3 d = r * std::cos(phi) * u + r * std::sin(phi) * v + std::sqrt(std::max(0.0, 1.0 - r * r)) * e.normal;
    ++count[fate(s, e, o, d)];
  }
  a.escaped += P * (double(count[0]) / M);
  a.back += P * (double(count[1]) / M);
  // Variance of the two binomial estimates, with half a count added on each side so that a leaf
  // with one ray does not claim to be exact.
  auto var = [&](int m) { return (m + 0.5) * (M - m + 0.5) / ((M + 1.0) * (M + 1.0) * M); };
  a.var += P * P * (var(count[0]) + var(count[1]));
}

/// The extension's light at a simulated leaf: directions it samples itself, each standing for a
/// share of its power; the variance from the spread of those shares.
void auditExtension(const SolverState& s, std::uint32_t i, double sent, LeafAudit& a) {
  const Element& e = s.h.element(i);
  const NodeId leaf{i};
  const Rgb P = s.ext->reflectedPower(leaf);
  if (maxComponent(P) <= 0.0) return;
  const int M = raysFor(luminance(P), sent);
  a.rays += std::uint64_t(M);
  Rng rng(s.opt.seed ^ 0xE57E4Dull, i);
  Rgb sum[3] = {Rgb(0.0), Rgb(0.0), Rgb(0.0)}, sum2[3] = {Rgb(0.0), Rgb(0.0), Rgb(0.0)};
  for (int k = 0; k < M; ++k) {
    Vec3 o = e.poly.sample(rng.uniform(), rng.uniform()), d(0.0);
    Rgb w = s.ext->sampleExitant(leaf, (k + rng.uniform()) / M, rng.uniform(), d);
    if (!allFinite(w) || maxComponent(w) <= 0.0 || glm::dot(d, d) <= 0.0) continue;
    int f = fate(s, e, o, glm::normalize(d));
    sum[f] += w, sum2[f] += w * w;
  }
  a.escaped += sum[0] / double(M);
  a.back += sum[1] / double(M);
  for (int f = 0; f < 2; ++f) a.var += glm::max(Rgb(0.0), sum2[f] / double(M) - (sum[f] / double(M)) * (sum[f] / double(M))) / double(M);
}

LeafAudit auditLeaf(const SolverState& s, std::uint32_t i, double sent) {
  const Element& e = s.h.element(i);
  LeafAudit a;
  // Absorbed: what arrived, less what the Lambertian part and the extension send on.
  a.absorbed = e.area * (Rgb(1.0) - s.mat(i).diffuse) * s.Et[i];
  auditLambertian(s, i, sent, a);
  if (s.ext && s.owned[i]) {
    a.absorbed -= s.ext->reflectedPower(NodeId{i});
    auditExtension(s, i, sent, a);
  }
  return a;
}

}  // namespace

AuditResult auditEnergy(SolverState& s) {
  PhaseTimer t(s.clkEnergy);
  const auto& els = s.h.elements();
  double sent = 0.0;
  for (std::size_t i = 0; i < els.size(); ++i) {
    if (!els[i].leaf()) continue;
    sent += luminance(s.B[i]) * els[i].area;
    if (s.ext && s.owned[i]) sent += luminance(s.ext->reflectedPower(NodeId{static_cast<std::uint32_t>(i)}));
  }
  std::vector<LeafAudit> per(els.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, els.size(), 64), [&](const auto& r) {
    s.clkEnergy.sawThread();
    for (std::size_t i = r.begin(); i != r.end(); ++i)
      if (els[i].leaf()) per[i] = auditLeaf(s, static_cast<std::uint32_t>(i), sent);
  });
  // Summed in element order: the totals do not depend on the thread count.
  AuditResult res;
  Rgb var(0.0);
  for (const LeafAudit& a : per) {
    res.escapedW += a.escaped;
    res.backAbsorbedW += a.back;
    res.absorbedW += a.absorbed + a.back;
    var += a.var;
    res.rays += a.rays;
  }
  res.escapedStdErrW = glm::sqrt(var);
  s.rays += res.rays;
  return res;
}

}  // namespace hr::detail
