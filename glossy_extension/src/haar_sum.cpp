// Re-projection of a sum of Haar trees. Terms in the target's frame are walked in lock-step with the
// target cell (a cursor per term: the node of that cell, or the leaf above it); a term in another
// frame is integrated over each target cell by descending its tree, taking whole cells inside the
// target cell at their mean and clipping leaf cells that straddle its edges. Where such a descent
// ended (those whole cells and straddling leaves: the cell's frontier) is where a sub-cell's descent
// starts, since nothing the target cell's descent pruned can meet a sub-cell: a pull of a curved
// VISION-like leaf's children, all in other frames, spent most of its time re-descending from the
// roots. The same cells are reached in the same order, so the sums are the same to the bit.
#include <glossy/cell_rules.h>
#include <glossy/haar_sum.h>
#include <glossy/spherical_geometry.h>

#include <algorithm>
#include <vector>

namespace glossy {

namespace {

using Node = HaarDistribution::Node;

Rgb value(const Node& n) { return {n.rgb[0], n.rgb[1], n.rgb[2]}; }

struct Rotated {
  const HaarDistribution* tree;
  Frame from;  // the term's frame; target-local directions are mapped through world coordinates
};

/// A source cell where a descent over a target cell ended (or one of the eight roots).
struct Visit {
  std::uint32_t node;
  int face, level;
  std::uint64_t index;
  FaceTri cell;
};
using Frontier = std::vector<Visit>;

class SumBuilder {
 public:
  SumBuilder(std::span<const HaarTerm> terms, const Frame& target, const HaarOptions& o, bool horizon)
      : target_(target), o_(o), horizon_(horizon) {
    for (const HaarTerm& t : terms) {
      if (t.frame.same(target))
        aligned_.push_back(t.tree);
      else
        rotated_.push_back({t.tree, t.frame});
      peak_ += hr::maxComponent(t.tree->peak());
    }
    cursors_.assign(std::size_t(o.maxLevel + 2) * 4 * std::max<std::size_t>(aligned_.size(), 1), 0);
    // Per level, each of a cell's four sub-cells' frontiers per rotated term; then the faces' own.
    // (A leaf's own projection sums one aligned term: nothing to allocate there.)
    if (rotated_.empty()) return;
    frontiers_.resize((std::size_t(o.maxLevel + 2) * 4 + 8) * rotated_.size());
    roots_.reserve(8);
    for (int f = 0; f < 8; ++f) roots_.push_back({std::uint32_t(f), f, 0, std::uint64_t(f), octaRoot(f)});
  }

  HaarDistribution build(HaarSumStats* stats) {
    nodes_.assign(8, Node{{0, 0, 0}, 0});
    std::vector<std::uint32_t> roots(aligned_.size());
    // Under a horizon the lower faces stay zero leaves: a term in a slightly tilted frame (a curved
    // leaf's part from before a split) would otherwise leave light below the surface.
    const std::size_t nr = rotated_.size();
    for (std::uint32_t f = 0; f < (horizon_ ? 4u : 8u); ++f) {
      for (std::size_t a = 0; a < aligned_.size(); ++a) roots[a] = f;
      FaceTri t = octaRoot(int(f));
      Frontier* to = nr ? &frontiers_[frontiers_.size() - 8 * nr + f * nr] : nullptr;
      buildCell(f, t, 0, meanOver(t, roots.data(), &roots_, 0, to), roots.data(), to);
    }
    if (stats) *stats = stats_;
    return HaarDistribution::fromNodes(std::move(nodes_));
  }

 private:
  /// Exact mean of the sum over target cell t; cur holds the aligned terms' nodes for t, from[r * stride]
  /// the frontier of rotated term r over a cell holding t (stride 0: one for all, the roots), and to[r]
  /// receives its frontier over t.
  Rgb meanOver(const FaceTri& t, const std::uint32_t* cur, const Frontier* from, std::size_t stride, Frontier* to) {
    Rgb sum(0.0);
    for (std::size_t a = 0; a < aligned_.size(); ++a) sum += value(aligned_[a]->nodes()[cur[a]]);
    if (!rotated_.empty()) {
      Rgb integral(0.0);
      for (std::size_t r = 0; r < rotated_.size(); ++r) integral += integrate(rotated_[r], t, from[r * stride], to[r]);
      sum += integral / t.solidAngle();
    }
    return sum;
  }

  /// Integral (W) of a rotated term over target cell t, descending from the cells of `from`.
  Rgb integrate(const Rotated& r, const FaceTri& t, const Frontier& from, Frontier& to) {
    Vec3 c[3];
    for (int k = 0; k < 3; ++k) c[k] = glm::normalize(r.from.toLocal(target_.toWorld(t.dir(k))));
    Cell cell{SphericalPolygon::triangle(c[0], c[1], c[2]), {}, Cap::around(FaceTri{{c[0], c[1], c[2]}})};
    insideNormals(c[0], c[1], c[2], cell.inward);
    Rgb acc(0.0);
    to.clear();
    for (const Visit& v : from) visit(*r.tree, v.node, v.cell, v.face, v.level, v.index, cell, acc, to);
    return acc;
  }

  struct Cell {
    SphericalPolygon poly;
    Vec3 inward[3];
    Cap cap;
  };

  /// face, level and index name the source cell for the tables of caps and solid angles (CellGeometry).
  void visit(const HaarDistribution& s, std::uint32_t i, const FaceTri& st, int face, int level, std::uint64_t index,
             const Cell& cell, Rgb& acc, Frontier& to) {
    const Node& n = s.nodes()[i];
    if (n.rgb[0] == 0.0f && n.rgb[1] == 0.0f && n.rgb[2] == 0.0f) return;  // non-negative: all zero below
    const CellGeometry g(st, face, level, index);
    if (!g.cap.overlaps(cell.cap)) return;
    const Vec3 d[3] = {st.dir(0), st.dir(1), st.dir(2)};  // (each a normalisation: once, not per plane)
    bool inside = true;
    for (int k = 0; k < 3 && inside; ++k)
      for (int j = 0; j < 3 && inside; ++j) inside = glm::dot(d[k], cell.inward[j]) >= 0.0;
    if (inside) {  // the whole source cell lies in the target cell: its mean is exact
      acc += value(n) * g.solidAngle(st);
      to.push_back({i, face, level, index, st});
      return;
    }
    if (n.child == 0) {
      to.push_back({i, face, level, index, st});
      SphericalPolygon p = cell.poly;
      Vec3 m[3];
      insideNormals(d[0], d[1], d[2], m);
      for (const Vec3& plane : m) p.clip(plane);
      ++stats_.clips;
      acc += value(n) * p.area();
      return;
    }
    for (std::uint32_t k = 0; k < 4; ++k)
      visit(s, n.child + k, st.child(int(k)), face, level + 1, 4 * index + k, cell, acc, to);
  }

  bool wide(const Rgb m[4], const Rgb& mean) const {
    double spread = 0.0, centre = 0.0;
    for (int c = 0; c < 3; ++c) {
      double lo = std::min({m[0][c], m[1][c], m[2][c], m[3][c]}), hi = std::max({m[0][c], m[1][c], m[2][c], m[3][c]});
      spread = std::max(spread, hi - lo);
      centre = std::max(centre, std::abs(mean[c]));
    }
    if (o_.refiner == Refiner::Absolute) return spread > o_.eps;
    return spread > o_.eps * std::max(centre, o_.floor * peak_);
  }

  /// fr: the rotated terms' frontiers over t, one per term.
  void buildCell(std::uint32_t idx, const FaceTri& t, int level, const Rgb& mean, const std::uint32_t* cur,
                 const Frontier* fr) {
    ++stats_.cells;
    Node& self = nodes_[idx];
    for (int c = 0; c < 3; ++c) self.rgb[c] = static_cast<float>(mean[c]);
    if (level >= o_.maxLevel) return;
    bool varies = !rotated_.empty();
    for (std::size_t a = 0; a < aligned_.size() && !varies; ++a) varies = aligned_[a]->nodes()[cur[a]].child != 0;
    if (!varies) return;  // every term is constant over the cell
    const std::size_t na = aligned_.size();
    std::uint32_t* next = &cursors_[std::size_t(level) * 4 * std::max<std::size_t>(na, 1)];
    const std::size_t nr = rotated_.size();
    Frontier* sub = nr ? &frontiers_[std::size_t(level) * 4 * nr] : nullptr;
    FaceTri ct[4];
    Rgb cm[4];
    for (int k = 0; k < 4; ++k) {
      ct[k] = t.child(k);
      for (std::size_t a = 0; a < na; ++a) {
        const Node& n = aligned_[a]->nodes()[cur[a]];
        next[std::size_t(k) * na + a] = n.child == 0 ? cur[a] : n.child + std::uint32_t(k);
      }
      cm[k] = meanOver(ct[k], next + std::size_t(k) * na, fr, 1, nr ? sub + std::size_t(k) * nr : nullptr);
    }
    // The minimum level matters to point-sampled projections (peaks between samples); on exact means
    // it only applies where the sum does vary over the cell.
    bool differ = cm[0] != cm[1] || cm[0] != cm[2] || cm[0] != cm[3];
    if (!differ || !(level < o_.minLevel || wide(cm, mean))) return;
    auto first = static_cast<std::uint32_t>(nodes_.size());
    nodes_.resize(nodes_.size() + 4, Node{{0, 0, 0}, 0});
    nodes_[idx].child = first;
    // The cursors and frontiers of this level are overwritten by the children's own splits only at
    // deeper levels.
    for (int k = 0; k < 4; ++k)
      buildCell(first + std::uint32_t(k), ct[k], level + 1, cm[k], next + std::size_t(k) * na,
                nr ? sub + std::size_t(k) * nr : nullptr);
  }

  const Frame& target_;
  const HaarOptions& o_;
  std::vector<const HaarDistribution*> aligned_;
  std::vector<Rotated> rotated_;
  std::vector<std::uint32_t> cursors_;
  std::vector<Frontier> frontiers_;  // see the constructor
  Frontier roots_;
  std::vector<Node> nodes_;
  const bool horizon_;
  double peak_ = 0.0;
  HaarSumStats stats_;
};

}  // namespace

HaarDistribution haarSum(std::span<const HaarTerm> terms, const Frame& target, const HaarOptions& o, HaarSumStats* stats,
                         bool horizon) {
  SumBuilder b(terms, target, o, horizon);
  return b.build(stats);
}

}  // namespace glossy
