// The measurement of --basis auto (basis_rule.h). Why measure at run time instead of a table of
// exponents: the crossovers move with every setting (at the solve's defaults the tetrahedron of level 3
// never wins, while with tetra-level 4 against dir-max-level 4 it wins from about n = 50 to 150;
// docs/directional.md), so a fixed table would be right for one setting only. Each measurement costs a
// few milliseconds per basis and is made once per distinct exponent of a scene. Why the error is
// weighed by cost: the lobe's error alone picked SH-12 for the glossy sphere's floor (n = 30), five
// times the tetrahedron's solve time for a worse image (docs/directional.md).
#include <glossy/basis_rule.h>
#include <glossy/lobe.h>

#include <algorithm>
#include <cmath>

namespace glossy {

double solveCost(Basis b, std::size_t lobeCoefficients) {
  const double n = double(lobeCoefficients);
  switch (b) {
    case Basis::Haar: return n;                  // sphere: 2.0 / 5.3 / 12.9 s at 144 / 368 / 1,152
    case Basis::Tetra: return 211.0 + 0.17 * n;  // 3.3 / 4.4 / 7.9 s at 130 / 514 / 2,050 vertices
    case Basis::Sh: return 13.5 * n;             // 8.8 / 23.6 / 50.5 s at orders 8 / 12 / 16
  }
  return 0.0;
}

AutoChoice autoChoice(double exponent, const BasisSpec& spec) {
  AutoChoice c;
  if (!std::isfinite(exponent) || exponent < 0.0) return c;
  LobeSpec lobe;
  lobe.exponent = exponent;
  lobe.asSolved = true;
  // 2^13 directions: the estimate's noise (about 1 %) only matters where two bases are that close,
  // and there either choice costs as much error.
  lobe.errorDirections = 1 << 13;
  double best = 0.0;
  for (Basis b : {Basis::Haar, Basis::Tetra, Basis::Sh}) {
    const auto k = std::size_t(b);
    // A surface reflects light from every incidence, and a lobe near the horizon is clipped and
    // skewed: three incidences, not one (at 30 degrees alone the glossy sphere's n = 40 went to Haar
    // by 2 %, and its image was 15 % worse than the tetrahedron's in 1.5 times the time).
    double err = 0.0, coef = 0.0;
    for (double deg : {0.0, 30.0, 60.0}) {
      lobe.incidentDeg = deg;
      LobeReport r = analyzeLobe(lobe, spec.with(b), false);
      err += r.l2RelError / 3.0;
      coef += double(r.coefficients) / 3.0;
    }
    c.l2RelError[k] = err;
    c.coefficients[k] = std::size_t(coef + 0.5);
    c.cost[k] = solveCost(b, c.coefficients[k]);
    c.merit[k] = std::max(c.l2RelError[k], kErrorFloor) * std::pow(c.cost[k], kCostExponent);
    // Strictly smaller wins: a tie keeps the earlier basis (Haar, then the tetrahedron).
    if (b == Basis::Haar || c.merit[k] < best) best = c.merit[k], c.basis = b;
  }
  return c;
}

}  // namespace glossy
