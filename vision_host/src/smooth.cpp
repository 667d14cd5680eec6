// Smooth display on the VISION-like host (issue 14): elements are rectangles of a primitive's
// parameter square, so the leaves of one primitive meet at parameter-space vertices. A vertex where
// leaves meet corner to corner takes the area-weighted mean radiosity of those leaves; a vertex that
// lies inside the edge of a larger leaf (a T-junction between levels) takes the value that larger
// leaf's edge shows there (linear in the parameter between its corners), so the display has no jump
// along the edge. Vertices are matched by their world position within one primitive, which joins
// the seam of a sphere, cylinder or disk (u = 0 and u = 1) and its poles or centre. Nothing blends
// across primitives (so never across materials or emitters), and a visible leaf never takes the
// radiosity of a hidden one (the no-halo rule of hr::reconstruct: a floor under a block is dark for a
// reason that stops at the block's edge).
#include "smooth.h"

#include <hr/solution.h>

#include <cmath>
#include <map>
#include <unordered_map>
#include <unordered_set>

namespace vision {
namespace {

struct Edge {
  double a0, a1;  // the edge's extent along its own parameter
  std::uint32_t leaf;
  int c0, c1;     // the leaf's corners at a0 and a1
  bool alongU;    // the edge runs along u (at constant v)
};

class SurfaceSmoother {
 public:
  SurfaceSmoother(const Surface& s, const std::vector<const Element*>& all, const std::vector<std::uint32_t>& mine,
                  const std::vector<char>& hidden, std::vector<LeafCorners>& out)
      : s_(s), all_(all), mine_(mine), hidden_(hidden), out_(out) {
    hr::Aabb box;
    for (std::uint32_t i : mine) box.grow(all[i]->g.box.lo), box.grow(all[i]->g.box.hi);
    q_ = std::max(box.diagonal(), 1e-300) * 1e-7;
    periodic_ = near(s.point(0.0, 0.5), s.point(1.0, 0.5)) && near(s.point(0.0, 0.25), s.point(1.0, 0.25));
    for (std::uint32_t i : mine) {
      const Rect& r = all[i]->rect;
      for (int k = 0; k < 4; ++k) at_[key(corner(i, k))].push_back({i, k});
      alongU_[r.v0].push_back({r.u0, r.u1, i, 0, 1, true});
      alongU_[r.v1].push_back({r.u0, r.u1, i, 3, 2, true});
      alongV_[wrap(r.u0)].push_back({r.v0, r.v1, i, 0, 3, false});
      alongV_[wrap(r.u1)].push_back({r.v0, r.v1, i, 1, 2, false});
    }
  }

  void run() {
    for (std::uint32_t i : mine_)
      for (int k = 0; k < 4; ++k) value(i, k);
    // The mean passes of hr::reconstruct: each corner-to-corner vertex moves by its leaves' mean
    // shortfall (a leaf's radiosity less the mean of its bilinear corners), within their range; a
    // T-junction follows the larger leaf's edge as before.
    for (std::uint32_t n = 0; n < mine_.size(); ++n) pos_[mine_[n]] = n;
    shortfall_.resize(mine_.size());
    prev_.resize(mine_.size());
    for (int pass = 0; pass < hr::kMeanPasses; ++pass) {
      for (std::uint32_t n = 0; n < mine_.size(); ++n) {
        const LeafCorners& c = out_[mine_[n]];
        prev_[n] = c;
        shortfall_[n] = all_[mine_[n]]->B - 0.25 * (c[0] + c[1] + c[2] + c[3]);
      }
      done_.clear();
      correcting_ = true;
      for (std::uint32_t i : mine_)
        for (int k = 0; k < 4; ++k) value(i, k);
    }
  }

 private:
  struct Ref {
    std::uint32_t leaf;
    int corner;
  };

  bool near(const Vec3& a, const Vec3& b) const { return glm::length(a - b) <= 2.0 * q_; }
  double wrap(double u) const { return periodic_ && u == 1.0 ? 0.0 : u; }
  static void uv(const Rect& r, int k, double& u, double& v) {
    u = (k == 1 || k == 2) ? r.u1 : r.u0;
    v = k >= 2 ? r.v1 : r.v0;
  }
  Vec3 corner(std::uint32_t i, int k) const {
    double u, v;
    uv(all_[i]->rect, k, u, v);
    return s_.point(wrap(u), v);  // the seam's two sides as one point, bit for bit
  }
  std::uint64_t key(const Vec3& p) const {
    auto c = [&](double x) { return static_cast<std::uint64_t>(std::llround(x / q_)); };
    return c(p.x) * 73856093ull ^ c(p.y) * 19349663ull ^ c(p.z) * 83492791ull;
  }
  /// The one larger leaf whose edge passes through corner k of leaf i (not at its ends), if its light
  /// may reach leaf i's corner; its edge.
  const Edge* tJunction(std::uint32_t i, int k, const Vec3& p) const {
    double u, v;
    uv(all_[i]->rect, k, u, v);
    auto search = [&](const std::map<double, std::vector<Edge>>& m, double line, double along) -> const Edge* {
      auto it = m.find(line);
      if (it == m.end()) return nullptr;
      for (const Edge& e : it->second) {
        if (e.leaf == i || !(e.a0 < along && along < e.a1)) continue;
        if (hidden_[e.leaf] && !hidden_[i]) continue;
        // A collapsed edge (a pole, a disk's centre) is one point: the corners there already meet.
        Vec3 end0 = e.alongU ? s_.point(e.a0, line) : s_.point(line, e.a0);
        Vec3 end1 = e.alongU ? s_.point(e.a1, line) : s_.point(line, e.a1);
        if (near(p, end0) || near(p, end1)) continue;
        return &e;
      }
      return nullptr;
    };
    if (const Edge* e = search(alongU_, v, u)) return e;
    return search(alongV_, wrap(u), v);
  }

  const Rgb& value(std::uint32_t i, int k) {
    const std::uint64_t slot = std::uint64_t(i) * 4 + std::uint64_t(k);
    if (auto f = done_.find(slot); f != done_.end()) return out_[i][k];
    const Vec3 p = corner(i, k);
    Rgb result(0.0);
    if (const Edge* e = tJunction(i, k, p)) {
      double u, v;
      uv(all_[i]->rect, k, u, v);
      const double t = ((e->alongU ? u : v) - e->a0) / (e->a1 - e->a0);
      const Rgb a = value(e->leaf, e->c0), b = value(e->leaf, e->c1);  // larger leaf: the recursion ends
      result = (1.0 - t) * a + t * b;
    } else {
      double w = 0.0;
      Rgb lo(1e300), hi(-1e300);
      for (const Ref& r : at_.find(key(p))->second) {
        if (!near(corner(r.leaf, r.corner), p)) continue;  // hash collision
        if (hidden_[r.leaf] && !hidden_[i]) continue;
        const double a = all_[r.leaf]->g.area;
        const Rgb& B = all_[r.leaf]->B;
        result += a * (correcting_ ? shortfall_[pos_.at(r.leaf)] : B), w += a;
        lo = glm::min(lo, B), hi = glm::max(hi, B);
      }
      if (correcting_)
        result = w > 0.0 ? glm::clamp(prev_[pos_.at(i)][k] + result / w, lo, hi) : prev_[pos_.at(i)][k];
      else
        result = w > 0.0 ? result / w : all_[i]->B;
    }
    out_[i][k] = result;
    done_.insert(slot);
    return out_[i][k];
  }

  const Surface& s_;
  const std::vector<const Element*>& all_;
  const std::vector<std::uint32_t>& mine_;
  const std::vector<char>& hidden_;
  std::vector<LeafCorners>& out_;
  double q_ = 0.0;
  bool periodic_ = false;
  std::unordered_map<std::uint64_t, std::vector<Ref>> at_;
  std::map<double, std::vector<Edge>> alongU_, alongV_;  // edges at constant v (along u), at constant u
  std::unordered_set<std::uint64_t> done_;
  bool correcting_ = false;                           // a mean pass: vertices move by their leaves' shortfall
  std::unordered_map<std::uint32_t, std::uint32_t> pos_;  // leaf -> its place in mine_
  std::vector<Rgb> shortfall_;                         // per place in mine_
  std::vector<LeafCorners> prev_;                      // per place in mine_: the last pass's corners
};

}  // namespace

std::vector<LeafCorners> smoothCorners(const Hierarchy& h, const std::vector<const Element*>& leaves,
                                       const std::vector<char>& hidden) {
  std::vector<LeafCorners> out(leaves.size());
  std::vector<std::vector<std::uint32_t>> bySurface(h.surfaces().size());
  for (std::uint32_t i = 0; i < leaves.size(); ++i) bySurface[leaves[i]->surface].push_back(i);
  for (std::size_t s = 0; s < bySurface.size(); ++s) {
    if (bySurface[s].empty()) continue;
    SurfaceSmoother sm(h.surfaces()[s], leaves, bySurface[s], hidden, out);
    sm.run();
  }
  return out;
}

}  // namespace vision
