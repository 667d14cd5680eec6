// `--basis auto`: the basis a glossy material's distributions are held in. A solve holds the rho_s
// lobe alone (the host keeps rho_d) and a basis's relative error does not depend on the lobe's scale,
// so the Phong exponent decides, with the settings of each basis; the diffuse / specular split does
// not. The rule measures rather than guesses: each basis projects the material's lobe as a solve
// would (LobeSpec::asSolved, its errors and coefficients averaged over 0, 30 and 60 degrees
// incidence), and the basis whose relative L2 error, weighed by
// what it costs a solve, is smallest wins: max(error, kErrorFloor) x cost^kCostExponent, so that a
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

/// A lobe's relative L2 error below which no image measured got better: on the glossy sphere the
/// tetrahedron's level 5 (lobe error 0.037 at n = 30) and SH-16 (0.016) drew no better image than
/// the tetrahedron's level 4 (0.137), at 1.8 and 11 times its time. Errors are weighed from here up.
inline constexpr double kErrorFloor = 0.1;

/// What a glossy solve's time grows by with a distribution of basis b whose lobe measured
/// `lobeCoefficients`, in units of one Haar coefficient. Fitted to the glossy sphere's study, one
/// curve per basis (seconds at levels / orders 3-5, 8-16): Haar's time follows its coefficients
/// (adaptive: the lobe's own cells), the tetrahedron's is mostly fixed (locating a direction's face,
/// whatever the level) plus a little per vertex, and SH's follows its coefficients 13.5 times as
/// steeply (every harmonic at every evaluation, and its projection quadrature). A fixed model, not a
/// timing: the choice must not depend on the machine's load.
double solveCost(Basis b, std::size_t lobeCoefficients);

struct AutoChoice {
  Basis basis = Basis::Haar;
  std::array<double, 3> l2RelError{};          // per Basis (haar, tetra, sh), mean over the incidences
  std::array<std::size_t, 3> coefficients{};   // of the measured lobes (mean), per Basis
  std::array<double, 3> cost{};                // solveCost per Basis
  std::array<double, 3> merit{};               // max(l2RelError, kErrorFloor) * cost^kCostExponent: the smallest wins
};

/// The measurement behind the choice for a material of Phong exponent n >= 0 with the settings of
/// `spec` (its dir-*, tetra-level and sh-order all move the crossovers). Deterministic. A non-finite
/// or negative exponent gets Haar, measured as nothing.
AutoChoice autoChoice(double exponent, const BasisSpec& spec);
inline Basis autoBasis(double exponent, const BasisSpec& spec) { return autoChoice(exponent, spec).basis; }

}  // namespace glossy
