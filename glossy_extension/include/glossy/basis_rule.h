// `--basis auto`: the basis a glossy material's distributions are held in. A solve holds the rho_s
// lobe alone (the host keeps rho_d) and a basis's relative error does not depend on the lobe's scale,
// so the Phong exponent decides, with the settings of each basis; the diffuse / specular split does
// not. The rule measures rather than guesses: each basis projects the material's lobe as a solve
// would (LobeSpec::asSolved, 30 degrees incidence) and the smallest relative L2 error wins. Why that,
// and the crossovers it gives: docs/directional.md, "Choosing the basis per material".
#pragma once
#include <glossy/distribution.h>

#include <array>
#include <cstddef>

namespace glossy {

struct AutoChoice {
  Basis basis = Basis::Haar;
  std::array<double, 3> l2RelError{};          // per Basis (haar, tetra, sh)
  std::array<std::size_t, 3> coefficients{};   // of the measured lobe, per Basis
};

/// The measurement behind the choice for a material of Phong exponent n >= 0 with the settings of
/// `spec` (its dir-*, tetra-level and sh-order all move the crossovers). Deterministic. A non-finite
/// or negative exponent gets Haar, measured as nothing.
AutoChoice autoChoice(double exponent, const BasisSpec& spec);
inline Basis autoBasis(double exponent, const BasisSpec& spec) { return autoChoice(exponent, spec).basis; }

}  // namespace glossy
