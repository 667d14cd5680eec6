// Reflecting a leaf's Illumination Samples: dropping and merging samples, the lobe sum, and the
// projection into each basis (Haar by cell integrals at the stored levels, haar_lobes.cpp;
// tetrahedron and spherical harmonics on a lobe limited to what they can hold).
#include <glossy/brdf.h>
#include <glossy/haar_lobes.h>
#include <glossy/lobe_level.h>
#include <glossy/reflection.h>

#include "lobe_cache.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace glossy {

Rgb LobeSet::operator()(const Vec3& w) const {
  double c = glm::dot(normal, w);
  if (c <= 0.0) return Rgb(0.0);
  Rgb sum(0.0);
  for (const LobeSample& s : samples) {
    double a = glm::dot(s.mirror, w);
    if (a > 0.0) sum += s.weight * std::pow(std::min(a, 1.0), exponent);
  }
  evaluations += samples.size();
  return c * sum;
}

double mergeAngle(double exponent) { return phongLobeWidth(exponent) / 16.0; }

double representableExponent(const BasisSpec& b, double exponent) {
  auto widest = [&](double width) {
    // The exponent whose 1 % half-width is `width`: cos(width)^N = 0.01.
    double c = std::cos(std::min(width, 0.5 * kPi - 1e-9));
    return std::log(0.01) / std::log(c);
  };
  switch (b.basis) {
    case Basis::Haar: return exponent;
    case Basis::Tetra: {
      // Root edges of the tetrahedron span acos(-1/3) = 109.47 degrees; each level halves them.
      double spacing = std::acos(-1.0 / 3.0) / double(1 << b.tetraLevel);
      return std::min(exponent, widest(2.0 * spacing));
    }
    default: return std::min(exponent, widest(2.0 * kPi / b.shOrder));
  }
}

namespace {

/// Seeds of merge groups binned on a grid of cubes of side at least the chord of the merge angle, so
/// that every seed within that angle of a direction lies in the 27 cubes around it. Without it,
/// grouping a leaf's samples compared each with every group so far: quadratic in the samples, ~500 a
/// leaf on the Soda Shoppe. With no merging (angle 0) or an angle so small that the grid's
/// coordinates would not fit in 21 bits, every group is a candidate (a plain scan).
class MergeGrid {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;
  explicit MergeGrid(double angle) : none_(!(angle > 0.0)) {
    // A side a little longer than the chord, so that rounding never puts a seed within the angle two
    // cubes away.
    const double side = 2.0 * std::sin(0.5 * std::min(angle, kPi)) * (1.0 + 1e-6);
    scan_ = !(side > 2.0 / double(1 << 20));
    inv_ = scan_ ? 0.0 : 1.0 / side;
  }
  template <class F>
  void forNeighbours(const Vec3& d, F&& f) const {
    if (none_) return;  // no merging: no group is a candidate
    if (scan_) {
      for (std::uint32_t g : all_) f(g);
      return;
    }
    const auto c = coords(d);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = cells_.find(pack(c[0] + dx, c[1] + dy, c[2] + dz));
          if (it == cells_.end()) continue;
          for (std::uint32_t g = it->second; g != kNone; g = next_[g]) f(g);
        }
  }
  void insert(const Vec3& d, std::uint32_t g) {
    if (none_) return;
    if (scan_) {
      all_.push_back(g);
      return;
    }
    const auto c = coords(d);
    if (next_.size() <= g) next_.resize(g + 1, kNone);
    auto [it, fresh] = cells_.try_emplace(pack(c[0], c[1], c[2]), g);
    if (!fresh) next_[g] = it->second, it->second = g;
  }

 private:
  std::array<std::int64_t, 3> coords(const Vec3& d) const {
    return {std::int64_t(std::floor((d.x + 1.0) * inv_)), std::int64_t(std::floor((d.y + 1.0) * inv_)),
            std::int64_t(std::floor((d.z + 1.0) * inv_))};
  }
  static std::uint64_t pack(std::int64_t x, std::int64_t y, std::int64_t z) {
    // Offsets by 1 keep the neighbours of cell 0 non-negative; 21 bits a coordinate.
    return std::uint64_t(x + 1) | std::uint64_t(y + 1) << 21 | std::uint64_t(z + 1) << 42;
  }
  bool none_ = false, scan_ = true;
  double inv_ = 0.0;
  std::vector<std::uint32_t> all_, next_;
  std::unordered_map<std::uint64_t, std::uint32_t> cells_;
};

}  // namespace

LobeSet makeLobes(std::span<const hr::IncidentSample> samples, const Frame& frame, const Vec3& worldNormal, double area,
                  const Rgb& specular, double exponent, double merge, ReflectCounts& counts, int senderPoints,
                  double resolved) {
  LobeSet set;
  set.normal = glm::normalize(frame.toLocal(worldNormal));
  set.exponent = exponent;
  counts.received += samples.size();
  const Rgb scale = area * specular * ((exponent + 2.0) / (2.0 * kPi));
  struct Item {
    Vec3 mirror;
    Rgb e;
    double w;  // channel sum of E: the merge weight and order
    std::size_t index;
  };
  std::vector<Item> items;
  items.reserve(samples.size());
  // The lobe's 1/e half-width, or the distribution's resolution if coarser: a sender seen narrower
  // would be spread below what is stored (the Soda Shoppe's brass, n = 10^4: 0.8 degree lobes in
  // cells of 2.8 degrees; spreading there made every sample eight lobes and its solve five times as
  // long for nothing the cells could show).
  const double width = std::max(lobeWidth(exponent), resolved);
  const int points = std::clamp(senderPoints, 0, kSenderPoints);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto& s = samples[i];
    double len = glm::length(s.toSender);
    bool ok = hr::allFinite(s.irradiance) && hr::allFinite(s.toSender) && len > 0.0 &&
              glm::all(glm::greaterThanEqual(s.irradiance, Rgb(0.0))) && hr::maxComponent(s.irradiance) > 0.0;
    Vec3 wi = ok ? frame.toLocal(s.toSender / len) : Vec3(0.0);
    double cosI = glm::dot(set.normal, wi);
    if (!ok || !(cosI > 0.0)) {
      ++counts.dropped;
      continue;
    }
    const bool extended = points > 0 && s.distance > 0.0 && s.radius > 0.0 && std::isfinite(s.radius);
    const double seen = extended ? s.radius / s.distance : 0.0;
    if (!(seen > width)) {
      items.push_back({mirror(wi, set.normal), s.irradiance, s.irradiance.x + s.irradiance.y + s.irradiance.z, 0});
      continue;
    }
    // The sender's disk, seen from here: about one direction per lobe-sized patch of it, in pairs
    // opposite about the centre (so their mean is the centre's direction) on a sunflower over the disk
    // (each pair the centres of two equal shares of its area).
    const int pairs = std::max(1, std::min(points / 2, int(std::ceil(0.5 * (seen / width) * (seen / width)))));
    const double r = std::tan(std::min(seen, 1.2));  // a sender nearer than its own size: 1.2 rad at most
    Vec3 u, v;
    orthonormalBasis(wi, u, v);
    std::array<Vec3, kSenderPoints> dirs;
    int front = 0;
    for (int j = 0; j < pairs; ++j) {
      const Vec3 t = sunflowerPoint(u, v, r, j, pairs);
      for (const Vec3& d : {glm::normalize(wi + t), glm::normalize(wi - t)})
        if (glm::dot(set.normal, d) > 0.0) dirs[front++] = d;
    }
    if (front == 0) dirs[front++] = wi;
    // Equal solid angles of a sender of even radiance: each direction's irradiance goes with its cosine.
    double cosSum = 0.0;
    for (int j = 0; j < front; ++j) cosSum += glm::dot(set.normal, dirs[j]);
    for (int j = 0; j < front; ++j) {
      const Rgb e = s.irradiance * (glm::dot(set.normal, dirs[j]) / cosSum);
      items.push_back({mirror(dirs[j], set.normal), e, e.x + e.y + e.z, 0});
    }
    ++counts.spread;
    counts.spreadLobes += std::uint64_t(front - 1);
  }
  // Arrival order breaks ties (a spread sample's directions in their order on the sunflower).
  for (std::size_t k = 0; k < items.size(); ++k) items[k].index = k;
  // Brightest first (ties by arrival order): each sample joins the first kept sample within `merge`
  // of it, so every merged direction lies within `merge` of its group's brightest member.
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.w != b.w ? a.w > b.w : a.index < b.index; });
  struct Group {
    Vec3 seed, sum;
    Rgb e;
    std::size_t members = 0;
  };
  std::vector<Group> groups;
  const double cosMerge = merge > 0.0 ? std::cos(merge) : 2.0;
  MergeGrid grid(merge);
  for (const Item& it : items) {
    // The first group (in creation order) whose seed lies within `merge`: found among the seeds in
    // the neighbouring grid cells, the same group a scan of all of them would find.
    std::uint32_t found = MergeGrid::kNone;
    grid.forNeighbours(it.mirror, [&](std::uint32_t g) {
      if (g < found && glm::dot(groups[g].seed, it.mirror) >= cosMerge) found = g;
    });
    if (found == MergeGrid::kNone) {
      found = std::uint32_t(groups.size());
      groups.push_back({it.mirror, Vec3(0.0), Rgb(0.0), 0});
      grid.insert(it.mirror, found);
    }
    Group& g = groups[found];
    g.sum += it.w * it.mirror;
    g.e += it.e;
    ++g.members;
  }
  set.samples.reserve(groups.size());
  for (const Group& g : groups) {
    double len = glm::length(g.sum);
    set.samples.push_back({len > 0.0 ? g.sum / len : g.seed, scale * g.e, g.members == 1});
  }
  counts.kept += set.samples.size();
  return set;
}

AnyDistribution zeroDistribution(const BasisSpec& b) {
  switch (b.basis) {
    case Basis::Haar: return HaarDistribution();
    case Basis::Tetra: return TetraDistribution(b.tetraLevel);
    default: return ShDistribution(b.shOrder);
  }
}

namespace {

/// Runs f (a Haar integration) and adds its lobe evaluations and memo hits and misses to counts.
template <class F>
auto countedHaar(const LobeSet& lobes, ReflectCounts& counts, F&& f) {
  const LobeCache& memo = lobeCache();
  const std::uint64_t hits = memo.hits, misses = memo.misses;
  lobes.evaluations = 0;
  auto out = f(lobes.evaluations);
  counts.lobesFromMemo += memo.hits - hits;
  counts.lobesIntegrated += memo.misses - misses;
  counts.brdfEvaluations += lobes.evaluations;
  return out;
}

}  // namespace

AnyDistribution projectLobes(const LobeSet& lobes, const BasisSpec& b, ReflectCounts& counts, const HaarCellSums* base,
                             double scale) {
  if (b.basis == Basis::Haar) {
    if (lobes.samples.empty() && (!base || base->cells.empty())) return zeroDistribution(b);
    return countedHaar(lobes, counts, [&](std::uint64_t& e) { return projectLobesHaar(lobes, b.haar, e, base, scale); });
  }
  if (base) throw std::logic_error("reflection layers are Haar cell sums");
  if (lobes.samples.empty()) return zeroDistribution(b);
  AnyDistribution out;
  lobes.evaluations = 0;
  if (b.basis == Basis::Tetra) {
    out = TetraDistribution::project(lobes, b.tetraLevel);
  } else {
    // Gauss-Legendre nodes enough for a lobe limited to the order (representableExponent).
    out = ShDistribution::project(lobes, b.shOrder, std::max(4 * b.shOrder, 32));
  }
  counts.brdfEvaluations += lobes.evaluations;
  return out;
}

HaarCellSums integrateLobes(const LobeSet& lobes, int level, ReflectCounts& counts, const HaarCellSums* base) {
  return countedHaar(lobes, counts, [&](std::uint64_t& e) { return integrateLobesHaar(lobes, level, e, base, 1.0); });
}

}  // namespace glossy
