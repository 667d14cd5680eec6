// Vose's alias construction: cells below the mean are topped up from cells above it; leftovers
// (rounding) keep themselves with probability 1.
#include <ref/alias_table.h>

#include <stdexcept>

namespace ref {

AliasTable::AliasTable(const std::vector<double>& weights) {
  double total = 0.0;
  for (double w : weights) {
    if (!(w >= 0.0)) throw std::invalid_argument("alias table: negative or NaN weight");
    total += w;
  }
  if (!(total > 0.0)) throw std::invalid_argument("alias table: weights sum to zero");
  const std::size_t n = weights.size();
  cells_.assign(n, Cell{});
  pmf_.resize(n);
  std::vector<double> scaled(n);
  std::vector<std::uint32_t> small, large;
  for (std::size_t i = 0; i < n; ++i) {
    pmf_[i] = weights[i] / total;
    scaled[i] = pmf_[i] * double(n);
    (scaled[i] < 1.0 ? small : large).push_back(static_cast<std::uint32_t>(i));
  }
  while (!small.empty() && !large.empty()) {
    std::uint32_t s = small.back(), l = large.back();
    small.pop_back();
    cells_[s] = {scaled[s], l};
    scaled[l] -= 1.0 - scaled[s];
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  for (std::uint32_t i : large) cells_[i] = {1.0, i};
  for (std::uint32_t i : small) cells_[i] = {1.0, i};
}

}  // namespace ref
