// Upper bounds of a directional distribution over a cone of directions: what the refinement oracle
// reads to see a highlight that a receiver might catch (extension.h: intensityBound). Each bound is
// conservative for what the basis's eval() returns anywhere in the cone, by construction:
// - Haar: the largest value of the leaf cells whose hull caps meet the cone (exact up to the caps).
// - Tetrahedron: the largest vertex value of the triangles whose hull caps meet the cone (a linear
//   interpolant never exceeds its corners).
// - Spherical harmonics of order L: the largest value on a grid covering the cone to within h, plus
//   (L - 1) B h, where B bounds |f| on the sphere (addition theorem and Cauchy-Schwarz per band) and
//   (L - 1) B bounds the derivative along any great circle (Bernstein's inequality for trigonometric
//   polynomials of degree L - 1); never above B.
#pragma once
#include <glossy/distribution.h>
#include <glossy/spherical_geometry.h>

namespace glossy {

Rgb boundOver(const HaarDistribution& d, const Cap& cone);
Rgb boundOver(const TetraDistribution& d, const Cap& cone);
Rgb boundOver(const ShDistribution& d, const Cap& cone);

/// B above: a bound of |f| over the whole sphere, per channel.
Rgb shMagnitudeBound(const ShDistribution& d);

inline Rgb boundOver(const AnyDistribution& d, const Cap& cone) {
  return std::visit([&](const auto& x) { return boundOver(x, cone); }, d);
}

}  // namespace glossy
