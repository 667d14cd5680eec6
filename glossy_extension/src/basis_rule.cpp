// The measurement of --basis auto (basis_rule.h). Why measure at run time instead of a table of
// exponents: the crossovers move with every setting (at the solve's defaults the tetrahedron of level 3
// never wins, while with tetra-level 4 against dir-max-level 4 it wins from about n = 50 to 150;
// docs/directional.md), so a fixed table would be right for one setting only. Each measurement costs a
// few milliseconds per basis and is made once per distinct exponent of a scene. Why the error is
// weighed by cost: the lobe's error alone picked SH-12 for the glossy sphere's floor (n = 30), five
// times the tetrahedron's solve time for a worse image (docs/directional.md).
#include <glossy/basis_rule.h>
#include <glossy/lobe.h>

#include <cmath>

namespace glossy {

double evaluationCostNs(Basis b, const BasisSpec& spec) {
  switch (b) {
    case Basis::Haar: return 25.0;  // a descent of a few levels; the broad lobes' deeper trees dominate
    case Basis::Tetra: return 50.0;  // locate the face, interpolate three vertices: level hardly matters
    case Basis::Sh: return 2.0 * double(spec.shOrder) * double(spec.shOrder);  // every coefficient, every time
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
    LobeReport r = analyzeLobe(lobe, spec.with(b), false);
    const auto k = std::size_t(b);
    c.l2RelError[k] = r.l2RelError;
    c.coefficients[k] = r.coefficients;
    c.costNs[k] = evaluationCostNs(b, spec);
    c.merit[k] = r.l2RelError * std::pow(c.costNs[k], kCostExponent);
    // Strictly smaller wins: a tie keeps the earlier basis (Haar, then the tetrahedron).
    if (b == Basis::Haar || c.merit[k] < best) best = c.merit[k], c.basis = b;
  }
  return c;
}

}  // namespace glossy
