// Walker's alias table (Vose's construction): draws index i with probability w_i / sum w in O(1)
// from one uniform number, so that picking an emitter costs the same for three lights or thousands
// of emitting patches (a CDF search costs a log and a cache miss per level).
#pragma once
#include <cstdint>
#include <vector>

namespace ref {

class AliasTable {
 public:
  AliasTable() = default;
  /// Weights must be >= 0 with a positive sum.
  explicit AliasTable(const std::vector<double>& weights);

  /// Index drawn with probability pmf(i), from u uniform in [0, 1).
  std::uint32_t sample(double u) const {
    double x = u * double(cells_.size());
    std::uint32_t i = static_cast<std::uint32_t>(x);
    if (i >= cells_.size()) i = static_cast<std::uint32_t>(cells_.size() - 1);
    const Cell& c = cells_[i];
    return x - double(i) < c.keep ? i : c.alias;
  }
  double pmf(std::uint32_t i) const { return pmf_[i]; }
  std::size_t size() const { return cells_.size(); }
  bool empty() const { return cells_.empty(); }

 private:
  struct Cell {
    double keep = 1.0;        // probability of keeping i rather than taking the alias
    std::uint32_t alias = 0;
  };
  std::vector<Cell> cells_;
  std::vector<double> pmf_;
};

}  // namespace ref
