// Names of the bases for the command line and reports.
#include <glossy/distribution.h>

#include <stdexcept>

namespace glossy {

Basis parseBasis(const std::string& name) {
  if (name == "haar") return Basis::Haar;
  if (name == "tetra") return Basis::Tetra;
  if (name == "sh") return Basis::Sh;
  throw std::invalid_argument("unknown basis '" + name + "' (valid: haar, tetra, sh)");
}

const char* basisName(Basis b) {
  switch (b) {
    case Basis::Haar: return "haar";
    case Basis::Tetra: return "tetra";
    default: return "sh";
  }
}

std::string BasisSpec::describe() const {
  if (automatic)
    return "auto per material (" + with(Basis::Haar).describe() + "; " + with(Basis::Tetra).describe() + "; " +
           with(Basis::Sh).describe() + ")";
  switch (basis) {
    case Basis::Haar:
      return std::string("haar eps ") + std::to_string(haar.eps) + " levels " + std::to_string(haar.minLevel) + "-" +
             std::to_string(haar.maxLevel) + (haar.refiner == Refiner::Relative ? " relative" : " absolute");
    case Basis::Tetra: return "tetra level " + std::to_string(tetraLevel);
    default: return "sh order " + std::to_string(shOrder);
  }
}

}  // namespace glossy
