// Coplanar and near-coplanar overlap detection: patches are bucketed by their quantised normal
// (either facing) and their plane's offset in steps of the widest gap that may count; pairs within
// a bucket and the next one are tested for the gap rule (coplanar.h) and for interior overlap of
// their convex polygons (separating axes in the plane), so adjacent faces of one mesh, which only
// share an edge, do not count.
#include <hr/coplanar.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace hr {
namespace {

/// Interior overlap of two convex planar polygons with unit normal n, by separating axes: the edge
/// normals of both; a gap or mere touching (up to tol) on any axis separates them.
bool interiorsOverlap(const Polygon& a, const Polygon& b, const Vec3& n, double tol) {
  for (const Polygon* p : {&a, &b})
    for (int i = 0; i < p->n; ++i) {
      Vec3 axis = glm::cross(n, p->v[(i + 1) % p->n] - p->v[i]);
      double len = glm::length(axis);
      if (len == 0.0) continue;
      axis /= len;
      double lo1 = 1e300, hi1 = -1e300, lo2 = 1e300, hi2 = -1e300;
      for (int k = 0; k < a.n; ++k) lo1 = std::min(lo1, glm::dot(axis, a.v[k])), hi1 = std::max(hi1, glm::dot(axis, a.v[k]));
      for (int k = 0; k < b.n; ++k) lo2 = std::min(lo2, glm::dot(axis, b.v[k])), hi2 = std::max(hi2, glm::dot(axis, b.v[k]));
      if (hi1 <= lo2 + tol || hi2 <= lo1 + tol) return false;
    }
  return true;
}

/// 2 A / perimeter, a convex patch's size across: a square's half side, a disk's radius, a long
/// strip's width (its radius would be half its length).
double across(const Patch& p) {
  double perimeter = 0.0;
  for (int i = 0; i < p.poly.n; ++i) perimeter += glm::length(p.poly.v[(i + 1) % p.poly.n] - p.poly.v[i]);
  return perimeter > 0.0 ? 2.0 * p.area / perimeter : 0.0;
}

bool inside(const Polygon& p, const Vec3& n, const Vec3& x) {
  for (int i = 0; i < p.n; ++i)
    if (glm::dot(glm::cross(p.v[(i + 1) % p.n] - p.v[i], x - p.v[i]), n) < 0.0) return false;
  return true;
}

}  // namespace

CoplanarCover::CoplanarCover(const std::vector<Patch>& patches, double tol) : patches_(&patches) {
  // Buckets keyed by the quantised normal (either facing) and the plane's offset in steps of the
  // largest gap that may count (step); each bucket is searched together with the next one, so two
  // planes within a step of each other always meet. Normals are rounded to the nearest 1e-6, so that
  // an axis-aligned normal's zero and a transform's -6e-17 fall together; two normals that straddle
  // a rounding boundary are missed: acceptable, it takes a normal half a step off an axis.
  std::vector<double> reach(patches.size());  // the widest gap at which each patch covers
  double step = tol;
  for (std::size_t i = 0; i < patches.size(); ++i) step = std::max(step, reach[i] = kNearGap * across(patches[i]));
  step = std::max(step, 1e-300);
  using Key = std::tuple<long long, long long, long long, long long>;
  std::map<Key, std::vector<std::uint32_t>> buckets;
  std::vector<double> offset(patches.size());
  for (std::uint32_t i = 0; i < patches.size(); ++i) {
    const Patch& p = patches[i];
    // Opposite normals share a bucket: faces in contact (a lamp lying on a box's bottom) pair too.
    // The sign is chosen on the rounded normal, so that a transform's -6e-17 in place of a 0 does
    // not turn one of two opposite faces the other way.
    long long r[3];
    for (int k = 0; k < 3; ++k) r[k] = static_cast<long long>(std::llround(p.normal[k] / 1e-6));
    const bool flip = r[0] < 0 || (r[0] == 0 && (r[1] < 0 || (r[1] == 0 && r[2] < 0)));
    const double sign = flip ? -1.0 : 1.0;
    offset[i] = sign * glm::dot(p.normal, p.poly.v[0]);
    // Clamped before the cast (a scaled-down scene far from the origin: out of range is undefined).
    const double slab = std::clamp(std::floor(offset[i] / step), -4e18, 4e18);
    buckets[{flip ? -r[0] : r[0], flip ? -r[1] : r[1], flip ? -r[2] : r[2], static_cast<long long>(slab)}].push_back(i);
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;  // (covered, cover)
  for (auto& [key, own] : buckets) {
    std::vector<std::uint32_t> ids = own;
    auto next = buckets.find({std::get<0>(key), std::get<1>(key), std::get<2>(key), std::get<3>(key) + 1});
    if (next != buckets.end()) ids.insert(ids.end(), next->second.begin(), next->second.end());
    if (ids.size() < 2) continue;
    // Sweep along one in-plane axis so that only patches whose extents overlap are paired.
    const Vec3 n = patches[ids[0]].normal;
    Vec3 t = std::abs(n.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
    Vec3 u = glm::normalize(glm::cross(t, n));
    auto lo = [&](std::uint32_t i) {
      double m = 1e300;
      for (int k = 0; k < patches[i].poly.n; ++k) m = std::min(m, glm::dot(u, patches[i].poly.v[k]));
      return m;
    };
    auto hi = [&](std::uint32_t i) {
      double m = -1e300;
      for (int k = 0; k < patches[i].poly.n; ++k) m = std::max(m, glm::dot(u, patches[i].poly.v[k]));
      return m;
    };
    std::sort(ids.begin(), ids.end(), [&](std::uint32_t a, std::uint32_t b) { return lo(a) < lo(b) || (lo(a) == lo(b) && a < b); });
    for (std::size_t a = 0; a < ids.size(); ++a)
      for (std::size_t b = a + 1; b < ids.size() && lo(ids[b]) < hi(ids[a]); ++b) {
        std::uint32_t i = ids[a], j = ids[b];
        const bool opposite = glm::dot(patches[i].normal, patches[j].normal) < 0.0;
        const bool flush = std::abs(offset[i] - offset[j]) <= tol;
        if (opposite && !flush) continue;  // facing each other across a gap: light passes between
        // Flush: the smaller covers the larger. With a gap (same facing): the one in front covers
        // the one behind, whatever their sizes (a lamp 1 mm under a ceiling of smaller tiles), within
        // a hundredth of the front one's size across (kNearGap).
        bool iSmaller = patches[i].area < patches[j].area || (patches[i].area == patches[j].area && i > j);
        std::uint32_t cover = iSmaller ? i : j, covered = iSmaller ? j : i;
        if (!flush) {
          const double gap = glm::dot(patches[j].normal, patches[i].poly.v[0] - patches[j].poly.v[0]);  // i over j
          cover = gap > 0.0 ? i : j, covered = gap > 0.0 ? j : i;
          if (!(std::abs(gap) <= reach[cover])) continue;
        }
        if (!interiorsOverlap(patches[i].poly, patches[j].poly, n, tol)) continue;
        if (opposite) {
          // Faces in contact hide each other: light between touching opaque faces never gets out.
          pairs.emplace_back(i, j);
          pairs.emplace_back(j, i);
          continue;
        }
        pairs.emplace_back(covered, cover);
      }
  }
  // A pair within one bucket was met twice (with the bucket below and the one above).
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  if (pairs.empty()) return;
  first_.assign(patches.size() + 1, 0);
  for (const auto& pr : pairs) ++first_[pr.first + 1];
  for (std::size_t i = 1; i < first_.size(); ++i) first_[i] += first_[i - 1];
  for (const auto& pr : pairs) cover_.push_back(pr.second);
}

std::uint32_t CoplanarCover::coverOf(std::uint32_t p, const Vec3& x) const {
  if (cover_.empty()) return kNone;
  for (std::uint32_t k = first_[p]; k < first_[p + 1]; ++k) {
    const Patch& q = (*patches_)[cover_[k]];
    if (inside(q.poly, q.normal, x)) return cover_[k];
  }
  return kNone;
}

}  // namespace hr
