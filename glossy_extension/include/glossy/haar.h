// Adaptive Haar basis on the octahedron (paper §4.1): a directional distribution of radiant
// intensity (W/sr, RGB) that is constant over spherical triangles, stored as an adaptive 1->4 tree in
// one contiguous array. Eight roots (the octants), projection top-down: sample at a triangle's corners
// and centre and subdivide while the spread is too large, always down to min_level, never past
// max_level. Peak hints (the mirror directions of the light that made a glossy lobe) refine the cells
// that hold them down to the lobe's width, so that a lobe narrower than the sampling is not missed;
// hints are narrowed per cell to those whose cap meets it.
#pragma once
#include <glossy/spherical_geometry.h>

#include <algorithm>
#include <cstdint>
#include <iosfwd>
#include <span>
#include <vector>

namespace glossy {

enum class Refiner {
  Relative,  // subdivide while (max - min) > eps * |centre| (the paper's choice, §5.1)
  Absolute,  // subdivide while (max - min) > eps, in W/sr
};

struct HaarOptions {
  double eps = 0.5;
  int minLevel = 2;
  int maxLevel = 8;  // a level-8 cell spans about 0.35 degrees
  Refiner refiner = Refiner::Relative;
  /// Relative refiner: centre values below floor * (largest sample) count as that much, so that the
  /// far tails of a lobe (a huge relative variation of almost nothing) stay coarse.
  double floor = 1e-3;
};

/// A direction where the projected function peaks and the angular width (radians) of the peak.
struct PeakHint {
  Vec3 dir;
  double width;
};

class HaarDistribution {
 public:
  struct Node {
    float rgb[3];        // mean intensity over the cell, W/sr
    std::uint32_t child;  // first of four children; 0 for a leaf (the roots hold indices 0-7)
  };

  /// The zero distribution: eight leaf roots.
  HaarDistribution() : nodes_(8, Node{{0.0f, 0.0f, 0.0f}, 0}) {}

  /// Projects f (Vec3 unit direction -> Rgb) top-down.
  template <class F>
  static HaarDistribution project(F&& f, const HaarOptions& o, std::span<const PeakHint> hints = {});

  /// The value in direction d (unit or not, nonzero). Inline: it runs per vertex per frame.
  Rgb eval(const Vec3& d) const {
    Bary b = octaBary(d);
    std::uint32_t i = static_cast<std::uint32_t>(octaFace(d));
    while (nodes_[i].child != 0) {
      int k = descend(b);
      i = nodes_[i].child + static_cast<std::uint32_t>(k);
    }
    const float* v = nodes_[i].rgb;
    return {v[0], v[1], v[2]};
  }

  /// The node whose cell holds direction d (the leaf eval() reads) and, if asked, that cell, its level
  /// and its number at that level (face * 4^level + the base-4 path, as cell_rules.h numbers cells).
  std::uint32_t locate(const Vec3& d, FaceTri* cell = nullptr, int* level = nullptr, std::uint64_t* index = nullptr) const;

  /// A copy cut at maxLevel: a cut cell keeps its exact mean, so the power is unchanged; four equal
  /// leaves fold into their parent (exact, and it drops the zero faces below a local horizon).
  HaarDistribution truncated(int maxLevel) const;
  /// A tree from nodes laid out as this class keeps them (eight roots first, children after their
  /// parent in blocks of four, every inner value the solid-angle mean of its children).
  static HaarDistribution fromNodes(std::vector<Node> nodes);
  /// Power, W: the leaf cells' values times their solid angles, summed in double precision (the
  /// integral of exactly what eval() returns; integral() reads the float root means instead).
  Rgb leafIntegral() const;
  /// The largest value of any cell, per channel, W/sr.
  Rgb peak() const;

  void add(const HaarDistribution& other);
  void scale(double s);
  /// The power, W: integral of the intensity over the sphere (exact for the stored cells).
  Rgb integral() const;
  std::size_t coefficients() const { return nodes_.size(); }
  std::size_t leaves() const;
  std::size_t bytes() const { return sizeof(*this) + nodes_.capacity() * sizeof(Node); }
  int depth() const;

  void serialize(std::ostream& out) const;
  /// Reads what serialize wrote; throws std::runtime_error on a foreign or damaged stream.
  static HaarDistribution deserialize(std::istream& in);

  /// Calls visit(cell, level, value, key) for every leaf; key identifies the cell across
  /// distributions (root face and path).
  template <class V>
  void visitLeaves(V&& visit) const {
    for (int f = 0; f < 8; ++f) visitNode(static_cast<std::uint32_t>(f), octaRoot(f), 0, 8u + std::uint64_t(f), visit);
  }

  std::span<const Node> nodes() const { return nodes_; }

 private:
  template <class V>
  void visitNode(std::uint32_t i, const FaceTri& t, int level, std::uint64_t key, V& visit) const {
    const Node& n = nodes_[i];
    if (n.child == 0) {
      visit(t, level, Rgb(n.rgb[0], n.rgb[1], n.rgb[2]), key);
      return;
    }
    for (int k = 0; k < 4; ++k) visitNode(n.child + std::uint32_t(k), t.child(k), level + 1, key * 4 + std::uint64_t(k), visit);
  }
  void merge(std::uint32_t i, const HaarDistribution& o, std::uint32_t j);
  void addToSubtree(std::uint32_t i, const float* v);
  static void setValue(Node& n, const Rgb& v) {
    n.rgb[0] = static_cast<float>(v.x);
    n.rgb[1] = static_cast<float>(v.y);
    n.rgb[2] = static_cast<float>(v.z);
  }

  template <class F>
  friend struct HaarBuilder;
  std::vector<Node> nodes_;
};

/// The level at which an octahedron cell is about half a peak's width (cells at level L span about
/// 90 / 2^L degrees).
int hintLevel(double width);

template <class F>
struct HaarBuilder {
  F& f;
  const HaarOptions& o;
  std::span<const PeakHint> hints;
  std::vector<HaarDistribution::Node>& nodes;
  double peak = 0.0;  // largest sample so far (channel maximum), for the relative refiner's floor
  std::vector<Cap> hintCaps;           // the cap of each hint's width around its direction
  std::vector<int> hintLevels;         // the level each hint refines to
  std::vector<std::uint32_t> active;   // stack of the hints that may reach the cell being built

  Rgb sample(const Vec3& d) {
    Rgb v = f(d);
    peak = std::max(peak, hr::maxComponent(glm::abs(v)));
    return v;
  }
  /// Narrows the active hints [begin, end) to those whose cap meets cell t (conservative, by the
  /// cell's hull cap); returns where the cell's own list starts (it ends at active.size()).
  std::size_t narrowHints(const Cap& cell, std::size_t begin, std::size_t end) {
    std::size_t mine = active.size();
    for (std::size_t k = begin; k < end; ++k)
      if (hintCaps[active[k]].overlaps(cell)) active.push_back(active[k]);
    return mine;
  }
  /// True when the cell may overlap a hinted peak and is still coarser than the peak.
  bool hinted(std::size_t begin, int level) const {
    for (std::size_t k = begin; k < active.size(); ++k)
      if (level < std::min(o.maxLevel, hintLevels[active[k]])) return true;
    return false;
  }
  bool wide(const Rgb* s) const {
    double spread = 0.0, centre = 0.0;
    for (int c = 0; c < 3; ++c) {
      double lo = std::min({s[0][c], s[1][c], s[2][c], s[3][c]}), hi = std::max({s[0][c], s[1][c], s[2][c], s[3][c]});
      spread = std::max(spread, hi - lo);
      centre = std::max(centre, std::abs(s[3][c]));
    }
    if (o.refiner == Refiner::Absolute) return spread > o.eps;
    return spread > o.eps * std::max(centre, o.floor * peak);
  }
  /// Builds node i for cell t whose corner samples are given; the parent's hints are [hb, he).
  void build(std::uint32_t i, const FaceTri& t, int level, const Rgb corner[3], std::size_t hb, std::size_t he) {
    std::size_t mine = narrowHints(Cap::around(t), hb, he), mineEnd = active.size();
    Rgb s[4] = {corner[0], corner[1], corner[2], sample(t.centreDir())};
    bool split = level < o.maxLevel && (level < o.minLevel || hinted(mine, level) || wide(s));
    if (!split) {
      // Cell mean: the degree-2 triangle rule (centre 3/4, corners 1/12 each).
      HaarDistribution::setValue(nodes[i], 0.75 * s[3] + (s[0] + s[1] + s[2]) / 12.0);
      active.resize(mine);
      return;
    }
    Rgb m01 = sample(glm::normalize(t.p[0] + t.p[1])), m12 = sample(glm::normalize(t.p[1] + t.p[2])),
        m20 = sample(glm::normalize(t.p[2] + t.p[0]));
    const Rgb kc[4][3] = {{s[0], m01, m20}, {m01, s[1], m12}, {m20, m12, s[2]}, {m12, m20, m01}};
    auto first = static_cast<std::uint32_t>(nodes.size());
    nodes.resize(nodes.size() + 4, HaarDistribution::Node{{0, 0, 0}, 0});
    nodes[i].child = first;
    Rgb sum(0.0);
    double total = 0.0;
    for (int k = 0; k < 4; ++k) {
      FaceTri ct = t.child(k);
      build(first + std::uint32_t(k), ct, level + 1, kc[k], mine, mineEnd);
      double w = ct.solidAngle();
      const float* v = nodes[first + std::uint32_t(k)].rgb;
      sum += w * Rgb(v[0], v[1], v[2]);
      total += w;
    }
    HaarDistribution::setValue(nodes[i], sum / total);
    active.resize(mine);
  }
};

template <class F>
HaarDistribution HaarDistribution::project(F&& f, const HaarOptions& o, std::span<const PeakHint> hints) {
  HaarDistribution d;
  HaarBuilder<F> b{f, o, hints, d.nodes_, 0.0, {}, {}, {}};
  // The floor's scale starts from the hinted peaks, so that it does not depend on which octant
  // happens to be built first when a hint is given.
  for (std::uint32_t k = 0; k < hints.size(); ++k) {
    const PeakHint& h = hints[k];
    b.sample(glm::normalize(h.dir));
    b.hintCaps.push_back(Cap::cone(h.dir, std::cos(std::min(h.width, kPi))));
    b.hintLevels.push_back(hintLevel(h.width));
    b.active.push_back(k);
  }
  const std::size_t all = b.active.size();
  for (int face = 0; face < 8; ++face) {
    FaceTri t = octaRoot(face);
    Rgb c[3] = {b.sample(t.dir(0)), b.sample(t.dir(1)), b.sample(t.dir(2))};
    b.build(static_cast<std::uint32_t>(face), t, 0, c, 0, all);
  }
  d.nodes_.shrink_to_fit();  // a projected distribution is kept for the whole solve: hold no slack
  return d;
}

}  // namespace glossy
