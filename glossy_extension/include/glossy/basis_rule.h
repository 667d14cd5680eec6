// `--basis auto`: the basis a glossy material's distributions are held in. A solve holds the rho_s
// lobe alone (the host keeps rho_d) and a basis's relative error does not depend on the lobe's scale,
// so the Phong exponent decides, with the settings of each basis; the diffuse / specular split does
// not. The rule measures rather than guesses: each basis projects the material's lobe as a solve
// would (LobeSpec::asSolved, 30 degrees incidence), and the basis whose relative L2 error, weighed by
// what its distributions cost to evaluate, is smallest wins: error x cost^kCostExponent, so that a
// basis wins only if no other reaches its error sooner along the error-time curves the study
// measures. Why, and the crossovers it gives: docs/directional.md, "Choosing the basis per material".
#pragma once
#include <glossy/distribution.h>

#include <array>
#include <cstddef>

namespace glossy {

/// The slope of error against solve time along one basis's study curve (error ~ time^-0.25): the
/// glossy sphere's Haar levels 3 to 4 gave 0.26, SH orders 8 to 12 0.24 (docs/directional.md). A
/// basis twice as costly must therefore be 2^0.25 = 1.19 times as accurate to be worth it.
inline constexpr double kCostExponent = 0.25;

/// What one evaluation of a distribution of basis b costs at the settings of `spec`, in ns of the
/// CI machine type (bench_directional's "eval ns": Haar 10-28 by depth, tetrahedron 37-56, SH
/// 1.9-2.1 per coefficient). Evaluations (transfer, bounds, display, SH's projection quadrature)
/// are what a glossy solve's time follows across bases. A fixed model, not a timing: the choice
/// must not depend on the machine's load.
double evaluationCostNs(Basis b, const BasisSpec& spec);

struct AutoChoice {
  Basis basis = Basis::Haar;
  std::array<double, 3> l2RelError{};          // per Basis (haar, tetra, sh)
  std::array<std::size_t, 3> coefficients{};   // of the measured lobe, per Basis
  std::array<double, 3> costNs{};              // evaluationCostNs per Basis
  std::array<double, 3> merit{};               // l2RelError * costNs^kCostExponent: the smallest wins
};

/// The measurement behind the choice for a material of Phong exponent n >= 0 with the settings of
/// `spec` (its dir-*, tetra-level and sh-order all move the crossovers). Deterministic. A non-finite
/// or negative exponent gets Haar, measured as nothing.
AutoChoice autoChoice(double exponent, const BasisSpec& spec);
inline Basis autoBasis(double exponent, const BasisSpec& spec) { return autoChoice(exponent, spec).basis; }

}  // namespace glossy
