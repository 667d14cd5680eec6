// Cell integrals of Phong lobes at the stored maximum level, accumulated lobe by lobe over the cells
// each lobe reaches, then the fine tree of their exact means and its re-projection with the stored
// options. Scratch arrays are per thread (reflect runs concurrently across leaves) and cleared by the
// list of the cells touched, so a reflection costs what its lobes reach, not the whole level.
#include <glossy/cell_rules.h>
#include <glossy/haar_lobes.h>
#include <glossy/haar_sum.h>
#include <glossy/phong_power.h>

#include "lobe_cache.h"

#include <algorithm>
#include <cassert>
#include <cstring>
#include <stdexcept>

namespace glossy {

namespace {

constexpr double kReachCutoff = 1e-4;   // a lobe is left out of a cell where cos^n < this everywhere
constexpr double kRadonLimit = 1.6;     // h / sigma up to which Radon's 7 points suffice
constexpr double kDunavantLimit = 3.5;  // h / sigma up to which Dunavant's 16 points suffice
constexpr int kFinestLevel = 16;

/// How one reflection's lobes are integrated (they share the exponent).
struct Plan {
  int store = 0;  // the level whose cells accumulate the integrals (dir-max-level)
  int quad = 0;   // the level whose cells get the rule (>= store)
  CellRule rule = CellRule::Radon7;
  bool axisOnly = false;  // narrower than the finest cells: the whole integral to the axis's cell
  double cosReach = 0.0, sinReach = 1.0;
};

Plan makePlan(double exponent, int store) {
  Plan p;
  p.store = store;
  const double sigma = 1.0 / std::sqrt(std::max(exponent, 1.0));
  p.quad = store;
  while (cellSize(p.quad) > kDunavantLimit * sigma && p.quad < kFinestLevel) ++p.quad;
  p.axisOnly = cellSize(p.quad) > kDunavantLimit * sigma;
  p.rule = cellSize(p.quad) <= kRadonLimit * sigma ? CellRule::Radon7 : CellRule::Dunavant16;
  p.cosReach = exponent > 0.0 ? std::pow(kReachCutoff, 1.0 / exponent) : 0.0;
  p.sinReach = std::sqrt(std::max(0.0, 1.0 - p.cosReach * p.cosReach));
  return p;
}

/// Per thread: the integrals (W) of every level's cells up to the stored level, and the stored-level
/// cells written since the last clear.
struct Scratch {
  std::vector<std::vector<Rgb>> sums;
  std::vector<std::uint64_t> touched;
  void prepare(int store) {
    if (int(sums.size()) < store + 1) sums.resize(std::size_t(store) + 1);
    for (int l = 0; l <= store; ++l)
      if (sums[std::size_t(l)].empty()) sums[std::size_t(l)].assign(4ull << (2 * l), Rgb(0.0));
  }
};

Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

/// Two doubles (GCC/Clang vector extensions): a block of 8 points is 4 of them per coordinate, which
/// stays in registers through the squaring chain (a loop over arrays spilled to memory cost 3x).
using V2 = double __attribute__((vector_size(16)));

V2 load(const double* p) {
  V2 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// sum_k w_k max(0, m.d_k)^n over each of N blocks of 8 points (x[8], y[8], z[8], w[8]). The squaring
/// chain is latency-bound (each step waits for the last); N = 2 keeps 8 chains in flight.
template <int N>
void blockIntegrals(const double* const* blocks, const Vec3& m, const PhongPower& power, double* out) {
  constexpr int K = 4 * N;
  V2 c[K];
  for (int j = 0; j < K; ++j) {
    const double* b = blocks[j / 4] + 2 * (j % 4);
    c[j] = m.x * load(b) + m.y * load(b + kBlockPoints) + m.z * load(b + 2 * kBlockPoints);
  }
  if (power.fraction() != 0.0) {
    for (int j = 0; j < K; ++j) c[j] = V2{power(c[j][0]), power(c[j][1])};
  } else {
    const V2 zero = {0.0, 0.0}, one = {1.0, 1.0}, cut = {power.cutoff(), power.cutoff()};
    V2 r[K], x[K];
    for (int j = 0; j < K; ++j) {
      // Below the cutoff (or behind, or NaN) 0, which stays 0 through the chain. Not clamped to 1:
      // a dot of unit vectors exceeds 1 by an ulp at most, which moves c^n by n ulps.
      x[j] = c[j] > cut ? c[j] : zero;
      // n = 0: 1 wherever the lobe is (c > 0); otherwise the chain multiplies a 0 in where c is 0.
      r[j] = power.integerPart() != 0 ? one : (x[j] > zero ? one : zero);
    }
    for (std::uint32_t k = power.integerPart(); k != 0; k >>= 1) {
      if (k & 1u)
        for (int j = 0; j < K; ++j) r[j] *= x[j];
      for (int j = 0; j < K; ++j) x[j] *= x[j];
    }
    for (int j = 0; j < K; ++j) c[j] = r[j];
  }
  for (int i = 0; i < N; ++i) {
    const double* w = blocks[i] + 3 * kBlockPoints;
    V2 sum = load(w) * c[4 * i] + load(w + 2) * c[4 * i + 1] + load(w + 4) * c[4 * i + 2] + load(w + 6) * c[4 * i + 3];
    out[i] = sum[0] + sum[1];
  }
}

class Integrator {
 public:
  Integrator(const Plan& p, const PhongPower& power, Scratch& s) : p_(p), power_(power), s_(s) {
    for (int l = 0; l <= std::min(p.quad, UpperCells::kTableLevel); ++l) caps_[l] = UpperCells::caps(l).data();
    if (p.quad <= UpperCells::kTableLevel) points_ = UpperCells::points(p.quad, p.rule).data();
    // What the rule gives a lobe all of whose reach lies in one cell, but m_z: the cosine to the
    // normal is m_z times the lobe's own cosine plus a part odd about the axis, which integrates to 0.
    const double n = power_.exponent();
    whole_ = 2.0 * kPi * (1.0 - std::pow(std::max(p_.cosReach, 0.0), n + 2.0)) / (n + 2.0);
  }

  /// Clip mode: only the stored cells inside cell (level, index) count, summed into clipped(), and
  /// only the cells on the way to it are visited; the memo is read but not filled (its lists are whole).
  void clipTo(int level, std::uint64_t index) {
    clip_ = true;
    clipLevel_ = level;
    clipIndex_ = index;
  }
  Rgb clipped() const { return clipSum_; }

  void lobe(const LobeSample& lobe) {
    m_ = lobe.mirror;
    weight_ = lobe.weight;
    if (p_.axisOnly) {
      depositAxis();
      return;
    }
    // Narrow lobes in wide stored cells (the Soda Shoppe's n = 10^4 at directional level 2) mostly
    // lie inside one cell, whose integral is then known in closed form: no quadrature points, no memo
    // (re-aimed samples rarely repeat a direction, so the memo hit 0.1 % of such lobes).
    if (const std::uint64_t c = containingCell(); c != kNoCell) {
      deposit(c, whole_ * m_.z);
      return;
    }
    // The unit lobe's shares of the stored cells, from the memo or integrated now (lobe_cache.h);
    // either way deposited from the list, so a hit and a miss give the same bits. A lobe that will
    // not recur (a merged group's) is neither looked up nor kept.
    const LobeCache::Key key{{m_.x, m_.y, m_.z}, power_.exponent(), p_.store};
    std::span<const CellShare> shares;
    if (lobe.recurs && cache_.find(key, shares)) {
      ++cache_.hits;
    } else {
      ++cache_.misses;
      cells_.clear();
      blocks_.clear();
      deep_.clear();
      for (std::uint64_t f = 0; f < 4; ++f) visit(0, f);
      evaluate();
      shares = lobe.recurs && !clip_ ? cache_.insert(key, shares_) : std::span<const CellShare>(shares_);
    }
    for (const CellShare& c : shares) deposit(c.cell, c.integral);
  }
  std::uint64_t evaluations() const { return evaluations_; }

 private:
  static constexpr std::uint64_t kNoCell = ~std::uint64_t(0);

  /// The stored cell the lobe's reach (the cap where cos^n >= kReachCutoff) lies inside, or kNoCell.
  /// Cells are spherical triangles with great-circle edges (planar subdivisions of an octahedron face,
  /// seen from the centre), so the cap is inside when its axis is at least the cap's radius inside
  /// each edge's great circle; the upper faces' cells end at the horizon, so such a lobe sends nothing
  /// below it.
  std::uint64_t containingCell() const {
    if (!(p_.sinReach < 1.0) || p_.cosReach <= 0.0) return kNoCell;
    FaceTri t;
    const std::uint64_t i = axisCell(&t);
    if (i == kNoCell) return kNoCell;
    for (int e = 0; e < 3; ++e) {
      const Vec3 &a = t.p[e], &c = t.p[(e + 1) % 3], &o = t.p[(e + 2) % 3];
      Vec3 nrm = glm::cross(a, c);
      if (glm::dot(nrm, o) < 0.0) nrm = -nrm;
      if (glm::dot(m_, nrm) < p_.sinReach * glm::length(nrm)) return kNoCell;
    }
    return i;
  }

  bool reaches(const CellCap& c) const {
    if (c.cosR <= -p_.cosReach) return true;
    double cosSum = c.cosR * p_.cosReach - c.sinR * p_.sinReach;
    return m_.x * c.cx + m_.y * c.cy + m_.z * c.cz >= cosSum - 1e-9;
  }
  bool reaches(const FaceTri& t) const {
    Cap reach{m_, p_.cosReach, p_.sinReach};
    return reach.overlaps(Cap::around(t));
  }

  /// Whether cell (level, i) lies on the way to the clip cell or inside it (always, unclipped).
  bool onPath(int level, std::uint64_t i) const {
    if (!clip_) return true;
    return level <= clipLevel_ ? (clipIndex_ >> (2 * (clipLevel_ - level))) == i : (i >> (2 * (level - clipLevel_))) == clipIndex_;
  }

  void visit(int level, std::uint64_t i) {
    if (!onPath(level, i) || !reaches(caps_[level][i])) return;
    if (level == p_.quad) {
      const int blocks = ruleBlocks(p_.rule);
      cells_.push_back(i);
      for (int b = 0; b < blocks; ++b) blocks_.push_back(points_ + (std::size_t(i) * std::size_t(blocks) + std::size_t(b)) * kBlockDoubles);
      return;
    }
    if (level + 1 > UpperCells::kTableLevel) {
      FaceTri t = UpperCells::cell(level, i);
      for (int k = 0; k < 4; ++k) visitDeep(level + 1, 4 * i + std::uint64_t(k), t.child(k));
      return;
    }
    for (std::uint64_t k = 0; k < 4; ++k) visit(level + 1, 4 * i + k);
  }

  void visitDeep(int level, std::uint64_t i, const FaceTri& t) {
    if (!onPath(level, i) || !reaches(t)) return;
    if (level == p_.quad) {
      cells_.push_back(i);
      deep_.emplace_back();
      cellPoints(t, p_.rule, deep_.back());
      return;
    }
    for (int k = 0; k < 4; ++k) visitDeep(level + 1, 4 * i + std::uint64_t(k), t.child(k));
  }

  /// The rule over every cell collected for the lobe, two blocks at a time.
  void evaluate() {
    if (!deep_.empty())
      for (const CellPoints& cp : deep_)
        for (int b = 0; b < ruleBlocks(p_.rule); ++b) blocks_.push_back(cp.block[b]);
    const std::size_t nb = blocks_.size();
    values_.resize(nb);
    std::size_t k = 0;
    for (; k + 2 <= nb; k += 2) blockIntegrals<2>(&blocks_[k], m_, power_, &values_[k]);
    if (k < nb) blockIntegrals<1>(&blocks_[k], m_, power_, &values_[k]);
    // Quadrature cells are collected depth first, so those inside one stored cell are consecutive:
    // each stored cell gets one share, the sum of its quadrature cells' integrals.
    const int per = ruleBlocks(p_.rule), shift = 2 * (p_.quad - p_.store);
    shares_.clear();
    for (std::size_t c = 0; c < cells_.size(); ++c) {
      double s = 0.0;
      for (int b = 0; b < per; ++b) s += values_[c * std::size_t(per) + std::size_t(b)];
      const auto cell = std::uint32_t(cells_[c] >> shift);
      if (!shares_.empty() && shares_.back().cell == cell)
        shares_.back().integral += s;
      else
        shares_.push_back({cell, s});
    }
    evaluations_ += cells_.size() * std::uint64_t(rulePoints(p_.rule));
  }

  void deposit(std::uint64_t cell, double integral) {
    if (!(integral > 0.0)) return;
    if (clip_) {
      if (onPath(p_.store, cell)) clipSum_ += integral * weight_;
      return;
    }
    Rgb& v = s_.sums[std::size_t(p_.store)][cell];
    if (v == Rgb(0.0)) s_.touched.push_back(cell);
    v += integral * weight_;
  }

  /// The stored cell holding the lobe's axis (and, given tri, its triangle), or kNoCell for an axis on
  /// or below the horizon.
  std::uint64_t axisCell(FaceTri* tri = nullptr) const {
    const int f = octaFace(m_);
    if (f >= 4) return kNoCell;
    Bary b = octaBary(m_);
    FaceTri t = octaRoot(f);
    std::uint64_t i = std::uint64_t(f);
    for (int l = 0; l < p_.store; ++l) {
      const int k = descend(b);
      i = 4 * i + std::uint64_t(k);
      if (tri) t = t.child(k);
    }
    if (tri) *tri = t;
    return i;
  }

  /// The whole lobe, 2 pi / (n + 1) times the cosine at its axis, into the stored cell holding the axis.
  void depositAxis() {
    // An axis on or below the horizon sends nothing above it.
    if (const std::uint64_t i = axisCell(); i != kNoCell) deposit(i, 2.0 * kPi / (power_.exponent() + 1.0) * m_.z);
  }

  const Plan& p_;
  const PhongPower& power_;
  Scratch& s_;
  const CellCap* caps_[UpperCells::kTableLevel + 1] = {};
  const double* points_ = nullptr;
  std::vector<std::uint64_t> cells_;    // the lobe's cells at the quadrature level
  std::vector<const double*> blocks_;   // their point blocks, in order
  std::vector<CellPoints> deep_;        // points of cells below the tables
  std::vector<double> values_;
  std::vector<CellShare> shares_;       // the lobe's shares of the stored cells (a memo miss)
  LobeCache& cache_ = lobeCache();
  Vec3 m_{0, 0, 1};
  Rgb weight_{0.0};
  bool clip_ = false;
  int clipLevel_ = 0;
  std::uint64_t clipIndex_ = 0;
  Rgb clipSum_{0.0};
  double whole_ = 0.0;  // a unit lobe's integral inside one cell, over m_z (constructor)
  std::uint64_t evaluations_ = 0;
};

double solidAngleOf(int level, std::uint64_t i) {
  return level <= UpperCells::kTableLevel ? UpperCells::caps(level)[i].omega : UpperCells::cell(level, i).solidAngle();
}

void setMean(HaarDistribution::Node& n, const Rgb& integral, double omega) {
  Rgb v = integral / omega;
  for (int c = 0; c < 3; ++c) n.rgb[c] = static_cast<float>(v[c]);
}

/// The tree of exact means down to the stored level wherever a lobe reached (zero leaves elsewhere).
void buildFine(const Scratch& s, int store, int level, std::uint64_t i, std::uint32_t node,
               std::vector<HaarDistribution::Node>& nodes) {
  const Rgb& sum = s.sums[std::size_t(level)][i];
  setMean(nodes[node], sum, solidAngleOf(level, i));
  if (level == store || sum == Rgb(0.0)) return;
  auto first = static_cast<std::uint32_t>(nodes.size());
  nodes.resize(nodes.size() + 4, HaarDistribution::Node{{0, 0, 0}, 0});
  nodes[node].child = first;
  for (std::uint32_t k = 0; k < 4; ++k) buildFine(s, store, level + 1, 4 * i + k, first + k, nodes);
}

}  // namespace

namespace {

/// Fills the scratch's stored level with base * scale and then the lobes' integrals.
void deposit(Scratch& s, const LobeSet& lobes, int store, std::uint64_t& evaluations, const HaarCellSums* base,
             double scale) {
  s.prepare(store);
  if (base) {
    if (base->level != store) throw std::logic_error("Haar cell sums of another level");
    auto& sums = s.sums[std::size_t(store)];
    for (std::size_t k = 0; k < base->cells.size(); ++k) {
      Rgb& v = sums[base->cells[k]];
      if (v == Rgb(0.0)) s.touched.push_back(base->cells[k]);
      v += scale * base->values[k];
    }
  }
  if (lobes.samples.empty()) return;
  // The leaf's frame puts its normal on +z; the upper cells then hold everything it sends.
  assert(std::abs(lobes.normal.z - 1.0) < 1e-9);
  const Plan plan = makePlan(lobes.exponent, store);
  const PhongPower power(lobes.exponent);
  Integrator in(plan, power, s);
  for (const LobeSample& l : lobes.samples) in.lobe(l);
  evaluations += in.evaluations();
}

}  // namespace

HaarCellSums integrateLobesHaar(const LobeSet& lobes, int level, std::uint64_t& evaluations, const HaarCellSums* base,
                                double scale) {
  const int store = std::clamp(level, 0, 8);
  Scratch& s = scratch();
  deposit(s, lobes, store, evaluations, base, scale);
  HaarCellSums out;
  out.level = store;
  out.cells.reserve(s.touched.size());
  out.values.reserve(s.touched.size());
  auto& sums = s.sums[std::size_t(store)];
  for (std::uint64_t c : s.touched) {
    out.cells.push_back(std::uint32_t(c));
    out.values.push_back(sums[c]);
    sums[c] = Rgb(0.0);
  }
  s.touched.clear();
  return out;
}

Rgb integrateLobesInCell(const LobeSet& lobes, int store, int level, std::uint64_t index, std::uint64_t& evaluations) {
  store = std::clamp(store, 0, 8);
  if (lobes.samples.empty() || level < 0 || level > store) return Rgb(0.0);
  assert(std::abs(lobes.normal.z - 1.0) < 1e-9);
  const Plan plan = makePlan(lobes.exponent, store);
  const PhongPower power(lobes.exponent);
  Integrator in(plan, power, scratch());
  in.clipTo(level, index);
  for (const LobeSample& l : lobes.samples) in.lobe(l);
  evaluations += in.evaluations();
  return in.clipped();
}

HaarDistribution projectLobesHaar(const LobeSet& lobes, const HaarOptions& o, std::uint64_t& evaluations,
                                  const HaarCellSums* base, double scale) {
  const int store = std::clamp(o.maxLevel, 0, 8);
  Scratch& s = scratch();
  deposit(s, lobes, store, evaluations, base, scale);
  // Coarser levels: sums of their children, in the (deterministic) order the cells were touched.
  for (std::uint64_t c : s.touched)
    for (int l = store - 1; l >= 0; --l) s.sums[std::size_t(l)][c >> (2 * (store - l))] += s.sums[std::size_t(store)][c];
  std::vector<HaarDistribution::Node> nodes(8, HaarDistribution::Node{{0, 0, 0}, 0});
  for (std::uint32_t f = 0; f < 4; ++f) buildFine(s, store, 0, f, f, nodes);
  for (std::uint64_t c : s.touched)
    for (int l = store; l >= 0; --l) s.sums[std::size_t(l)][c >> (2 * (store - l))] = Rgb(0.0);
  s.touched.clear();
  HaarDistribution fine = HaarDistribution::fromNodes(std::move(nodes));
  HaarTerm term{&fine, Frame::world()};
  return haarSum({&term, 1}, Frame::world(), o);
}

}  // namespace glossy
