// Reflection of Illumination Samples at a glossy leaf (paper §3.3): each sample is a Dirac impulse of
// irradiance E_i from w_i, so the leaf's exitant intensity is the sum of impulse responses
//   I(w_o) = A cos(theta_o) sum_i f_s(w_i, w_o) E_i,  f_s = rho_s (N + 2) / (2 pi) cos^N(alpha_i),
// (W/sr; the host keeps rho_d), projected into the leaf's directional basis. Samples whose mirror
// directions nearly coincide are merged first (irradiance-weighted mean direction, summed irradiance;
// see glossy_extension/README.md for what it costs). Projection never misses a highlight:
// - Haar: every stored cell gets the integral of the lobes over it, by a cell quadrature fine enough
//   for the lobes' width (haar_lobes.h), and the stored tree is cut from these exact means with the
//   stored options (dir-eps, levels): the power is the lobes' even when a lobe is far narrower than a
//   cell of dir-max-level.
// - Tetrahedron and spherical harmonics sample the lobe at fixed points, so a lobe narrower than their
//   resolution would fall between the points: the exponent is first limited to what the basis can
//   hold (representableExponent), which widens the lobe and keeps its normalisation.
// A sample is one direction, but its sender is an area: one seen wider than the lobe (radius /
// distance > sqrt(2/N)) and than the stored cells is mirrored as its disk (IncidentSample::radius),
// not as a lobe about its centre, by spreading the sample's irradiance over up to kSenderPoints
// directions across the disk, about one per lobe- or cell-sized patch of it (a near card in a
// mirror came out as blobs about the centres of its elements; docs/glossy.md, "Senders as areas").
#pragma once
#include <glossy/distribution.h>
#include <glossy/frame.h>
#include <glossy/spherical_geometry.h>

#include <cstdint>
#include <span>
#include <vector>

namespace glossy {

/// One (possibly merged) sample ready for reflection, in the distribution's frame.
struct LobeSample {
  Vec3 mirror{0, 0, 1};  // unit mirror direction of the light's direction
  Rgb weight{0.0};       // W/sr: A rho_s (N + 2) / (2 pi) E, the lobe's peak per unit cos(theta_o)
  /// Whether the lobe's shape recurs from sweep to sweep (one sample's own mirror direction, fixed by
  /// its link), so the per-thread lobe memo should keep it; a merged group's direction is weighted by
  /// irradiances that change every sweep, and kept it only filled the memo.
  bool recurs = true;
};

struct ReflectCounts {
  std::uint64_t received = 0, kept = 0, dropped = 0, brdfEvaluations = 0;
  /// Samples spread over their sender's disk, and the lobes that added beyond one per sample.
  std::uint64_t spread = 0, spreadLobes = 0;
  /// Haar: lobes whose cell integrals came from the per-thread memo, and lobes integrated anew.
  std::uint64_t lobesFromMemo = 0, lobesIntegrated = 0;
};

/// The lobes of one leaf: I(w) = max(0, normal.w) sum_j weight_j max(0, mirror_j.w)^exponent.
struct LobeSet {
  Vec3 normal{0, 0, 1};  // in the distribution's frame
  double exponent = 1.0;
  std::vector<LobeSample> samples;
  mutable std::uint64_t evaluations = 0;  // lobe evaluations (one BRDF evaluation each)
  Rgb operator()(const Vec3& w) const;
};

/// Integrals (W) of a sum of lobes over the upper Haar cells of one level that it reaches, in the
/// order they were first reached: a reflection before its tree is cut, shared by the leaves below an
/// element (reflection is linear in the samples; docs/glossy.md, "Reflection in layers").
struct HaarCellSums {
  int level = 0;
  std::vector<std::uint32_t> cells;
  std::vector<Rgb> values;
};

/// The widest angular bin (radians) in which samples are merged, for a lobe of this exponent: 1/16
/// of its 1 % half-width.
double mergeAngle(double exponent);

/// The largest exponent a basis holds without its lobe falling between its sample points: Haar any;
/// tetrahedron level t a lobe at least two vertex spacings wide (1 % half-width); spherical harmonics
/// of order L a lobe at least 2 pi / L wide.
double representableExponent(const BasisSpec& b, double exponent);

/// The most directions one sample's sender is spread over: senders up to about 2.8 lobe widths
/// across get one direction per lobe-sized patch of their disk, wider ones fewer, at bounded cost (16
/// took the VISION-like host's glossy Cornell box from 43 to 60 s for the same image).
inline constexpr int kSenderPoints = 8;

/// The host's samples (world frame) as lobes in `frame`: samples with no light on the front of the
/// surface (non-finite, non-positive, or from behind) are dropped; with senderPoints > 0 a sample
/// whose sender is seen wider than the lobe and than `resolved` (rad: what the distribution holds,
/// e.g. its Haar cell) is spread over its disk (at most senderPoints directions, one per patch of
/// that width; those below the surface are left out and the rest share the whole irradiance by
/// their cosines); samples within `merge` radians of a brighter one are merged into it (0: no
/// merging). E is planar irradiance, W/m^2; area in m^2.
LobeSet makeLobes(std::span<const hr::IncidentSample> samples, const Frame& frame, const Vec3& worldNormal,
                  double area, const Rgb& specular, double exponent, double merge, ReflectCounts& counts,
                  int senderPoints = 0, double resolved = 0.0);

/// Projects the lobes into the basis (see the file comment); counts lobe evaluations. Haar only: with
/// base * scale added (cell sums at the stored level, integrateLobes).
AnyDistribution projectLobes(const LobeSet& lobes, const BasisSpec& b, ReflectCounts& counts,
                             const HaarCellSums* base = nullptr, double scale = 1.0);

/// base (when given) plus the lobes' integrals over the Haar cells of `level`, not yet cut into a tree:
/// the reflection of samples shared by every leaf below an element.
HaarCellSums integrateLobes(const LobeSet& lobes, int level, ReflectCounts& counts, const HaarCellSums* base = nullptr);

/// The zero distribution of a basis.
AnyDistribution zeroDistribution(const BasisSpec& b);

}  // namespace glossy
