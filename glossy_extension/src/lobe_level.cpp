// The per-material finest Haar level from the lobe's width (rule and constant: lobe_level.h).
#include <glossy/lobe_level.h>

#include <algorithm>
#include <cmath>

namespace glossy {

int lobeLevel(double exponent, int minLevel) {
  const int lo = std::max(minLevel, kLobeLevelCoarsest);
  if (!std::isfinite(exponent) || !(exponent > 0.0)) return std::min(lo, kLobeLevelFinest);
  const double pi = 3.14159265358979323846;
  // sqrt(pi/2) / 2^L <= sqrt(2/n)  <=>  L >= log2(pi n / 4) / 2; the small slack keeps an exact
  // boundary exponent on the coarser side regardless of rounding.
  const double need = 0.5 * std::log2(pi * exponent / 4.0) - 1e-9;
  const int level = need <= 0.0 ? 0 : int(std::ceil(need));
  return std::clamp(level, lo, std::max(lo, kLobeLevelFinest));
}

}  // namespace glossy
