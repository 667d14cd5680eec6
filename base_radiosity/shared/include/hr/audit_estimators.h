// The estimators behind every host's energy audit (the independent check that emitted power equals
// absorbed plus escaped power, measured without the host's interactions). A host walks its own
// leaves and traces against its own surfaces; what a leaf's rays and an extension's draws add up to,
// their variance, how the ray budget is shared and how the leaves' parts sum into the totals are
// the same on every host and live here once. The totals land in SolveStats through recordAudit(),
// which applies judgeEnergy()'s honest-reporting rule.
#pragma once
#include <hr/solve.h>

#include <cstdint>
#include <span>

namespace hr::audit {

/// Audit rays shared among the leaves in proportion to their power: the standard error of the
/// escaped power is then at most about 1/(2 sqrt(budget)) = 0.07 % of the emitted power, whatever
/// the leaf count (a fixed 64 rays per leaf spent 3.8 M rays on the Soda Shoppe's dark leaves).
constexpr double kRayBudget = 1 << 19;
/// Seeds (xor the run's seed) of the Lambertian rays and of the extension's draws, per leaf.
constexpr std::uint64_t kLambertianSeed = 0xE5CA9Eull, kExtensionSeed = 0xE57E4Dull;

/// Where a ray from a leaf ends: escaped the scene, absorbed by a black back (surfaces are
/// one-sided), or on a front (absorbed or sent on there by the host's own transport).
enum Fate : int { kEscaped = 0, kBack = 1, kFront = 2 };

/// One leaf's part of the audit, W per channel; var: variance of its escaped + back estimate, W^2.
struct LeafAudit {
  Rgb absorbed{0.0}, escaped{0.0}, back{0.0}, var{0.0};
  std::uint64_t rays = 0;
};

/// The audit's totals, W per channel: absorbed includes the back faces' part (backAbsorbed).
struct Totals {
  Rgb absorbed{0.0}, escaped{0.0}, back{0.0}, stdErr{0.0};
  std::uint64_t rays = 0;
};

/// How many rays a leaf sending luminance p of the total `sent` gets (at least one).
int raysFor(double p, double sent);

/// An orthonormal tangent pair (u, v) with u x v = n for a unit normal n.
void tangentFrame(const Vec3& n, Vec3& u, Vec3& v);

/// Ray k of M, cosine-distributed about n: a randomly shifted rank-1 lattice over
/// (sin^2 theta, phi), stratified for any M and unbiased (every ray is marginally uniform); jitter
/// in [0,1) moves the ray within its stratum. A square grid with sqrt(M) rounded left its outermost
/// ring short whenever M was not a square: a 1 % bias.
Vec3 latticeCosineDirection(const Vec3& n, const Vec3& u, const Vec3& v, double shift, int k, int M, double jitter);

/// Adds the Lambertian light P (W) of a leaf whose M rays (total weight `total`; M when unweighted)
/// ended with the given weights per Fate: escaped and back shares of P and their binomial variance,
/// with half a count added on each side so that a leaf with one ray does not claim to be exact.
void addLambertian(LeafAudit& a, const Rgb& P, const double weight[3], double total);

/// Adds an extension's light drawn as directions that each stand for a share of its power: sum and
/// sum2 are, per Fate, the sums of the shares and of their squares, total the draws' weight.
void addDrawn(LeafAudit& a, const Rgb sum[3], const Rgb sum2[3], double total);

/// The leaves' parts summed in the given order (so the totals do not depend on the thread count).
Totals sum(std::span<const LeafAudit> leaves);

/// Writes the totals into the statistics and judges them (judgeEnergy): an imbalance beyond
/// maxImbalance of the emitted power plus the audit's own noise clears energyOk.
void record(SolveStats& st, const Totals& t, double maxImbalance);

}  // namespace hr::audit
