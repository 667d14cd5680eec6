// One interface over the three directional bases. Hot loops use the concrete types (their eval is
// inline, no virtual call); code that picks a basis at run time holds an AnyDistribution (a variant,
// dispatched once per call, not per basis function). The concept states what every basis offers.
#pragma once
#include <glossy/haar.h>
#include <glossy/sh.h>
#include <glossy/tetra.h>

#include <concepts>
#include <iosfwd>
#include <span>
#include <string>
#include <variant>

namespace glossy {

template <class D>
concept DirectionalDistribution = requires(const D c, D m, const Vec3 v, double s, std::ostream& out) {
  { c.eval(v) } -> std::same_as<Rgb>;
  { c.integral() } -> std::same_as<Rgb>;
  { c.coefficients() } -> std::convertible_to<std::size_t>;
  { c.bytes() } -> std::convertible_to<std::size_t>;
  m.add(c);
  m.scale(s);
  c.serialize(out);
};
static_assert(DirectionalDistribution<HaarDistribution>);
static_assert(DirectionalDistribution<TetraDistribution>);
static_assert(DirectionalDistribution<ShDistribution>);

enum class Basis { Haar, Tetra, Sh };

/// Everything needed to project into one of the bases.
struct BasisSpec {
  Basis basis = Basis::Haar;
  HaarOptions haar;
  int tetraLevel = 3;
  int shOrder = 8;
  int shQuadrature = 0;  // 0: automatic
  /// --basis auto: each glossy material gets the basis basis_rule.h picks for its exponent (with the
  /// settings above); `basis` is then only the default of code that projects without a material.
  bool automatic = false;
  /// --dir-max-level was given: haar.maxLevel is a hard cap for every material. Otherwise each glossy
  /// material gets its own finest level from its lobe's width (lobe_level.h), haar.maxLevel being the
  /// finest of those in use.
  bool haarLevelGiven = false;
  std::string describe() const;
  /// This spec for one basis (not automatic): what a node of that basis is projected with.
  BasisSpec with(Basis b) const {
    BasisSpec s = *this;
    s.basis = b;
    s.automatic = false;
    return s;
  }
};

/// Parses "haar", "tetra" or "sh"; throws std::invalid_argument listing the valid names.
Basis parseBasis(const std::string& name);
const char* basisName(Basis b);

using AnyDistribution = std::variant<HaarDistribution, TetraDistribution, ShDistribution>;

template <class F>
AnyDistribution project(const BasisSpec& spec, F&& f, std::span<const PeakHint> hints = {}) {
  switch (spec.basis) {
    case Basis::Haar: return HaarDistribution::project(f, spec.haar, hints);
    case Basis::Tetra: return TetraDistribution::project(f, spec.tetraLevel);
    default: return ShDistribution::project(f, spec.shOrder, spec.shQuadrature);
  }
}

inline Rgb eval(const AnyDistribution& d, const Vec3& v) {
  return std::visit([&](const auto& x) { return x.eval(v); }, d);
}
inline Rgb integral(const AnyDistribution& d) {
  return std::visit([](const auto& x) { return x.integral(); }, d);
}
inline std::size_t coefficients(const AnyDistribution& d) {
  return std::visit([](const auto& x) { return x.coefficients(); }, d);
}
inline std::size_t bytes(const AnyDistribution& d) {
  return std::visit([](const auto& x) { return x.bytes(); }, d);
}

}  // namespace glossy
