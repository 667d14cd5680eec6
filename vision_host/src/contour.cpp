// Point-to-element form factors by Lambert's contour integral: the projected solid angle of a surface
// depends only on its boundary, so a planar element (straight or arc edges) and a curved element
// that faces the point everywhere and lies above its horizon are both integrated exactly along
// their outline (arcs as chords turning at most about 3 degrees: the area lost in the slivers is
// below 1e-4 of the element's). Bounded by 1 for touching elements, unlike 1/r^2 sampling. A curved
// piece that x sees only in part (across its terminator or x's horizon) is split until its pieces
// are wholly seen or wholly unseen.
#include <hr/kernel.h>

#include <algorithm>
#include <cmath>

#include "state.h"

namespace vision::detail {
namespace {

constexpr double kChordTurn = 3.0 * hr::kPi / 180.0;

/// Chords per edge: one for a straight edge, enough for a 3-degree turn each along an arc.
int segments(const Surface& s, bool alongU, const Rect& r) {
  if (s.straightEdges()) return 1;
  if (alongU) return std::max(1, int(std::ceil(2.0 * hr::kPi * r.du() / kChordTurn)));
  if (s.kind != SurfaceKind::Sphere) return 1;  // radii and generators are straight
  double span = std::acos(std::clamp(1.0 - 2.0 * r.v1, -1.0, 1.0)) - std::acos(std::clamp(1.0 - 2.0 * r.v0, -1.0, 1.0));
  return std::max(1, int(std::ceil(std::abs(span) / kChordTurn)));
}

/// A disk's form factor for a piece too small to split further (bounded near contact, unlike 1/r^2).
double diskFormFactor(const Surface& sf, const Rect& r, const Vec3& x, const Vec3& n) {
  const double um = 0.5 * (r.u0 + r.u1), vm = 0.5 * (r.v0 + r.v1);
  const Vec3 y = sf.point(um, vm), d = x - y;
  const double area = sf.jacobian(um, vm) * r.du() * r.dv(), r2 = glm::dot(d, d);
  const double cy = glm::dot(sf.normal(um, vm), d), cx = -glm::dot(n, d);
  if (cy <= 0.0 || cx <= 0.0 || r2 <= 0.0) return 0.0;
  return area * cy * cx / (hr::kPi * (r2 * r2 + area * r2 / hr::kPi));
}

constexpr int kProbe = 3;      // probes per parameter direction, edges included
constexpr double kSmall = 0.01;  // a piece of area below this times its squared distance: one point

}  // namespace

double curvedFormFactor(const Surface& sf, const Rect& r, const Vec3& x, const Vec3& n) {
  thread_local CurvedPieces pieces(sf, r);
  pieces.reset(sf, r);
  return pieces.formFactor(x, n);
}

CurvedPieces::CurvedPieces(const Surface& sf, const Rect& r) : sf_(&sf), r_(r) {}

void CurvedPieces::reset(const Surface& sf, const Rect& r) {
  sf_ = &sf, r_ = r;
  std::fill(slot_.begin(), slot_.end(), -1);
  std::fill(outlineSlot_.begin(), outlineSlot_.end(), -1);
  p_.clear(), n_.clear();
  outlineCount_ = 0;
}

Rect CurvedPieces::rectOf(int depth, int i, int j) const {
  const int s = kN >> depth;
  auto at = [](double a, double b, int k) { return a + (b - a) * (double(k) / kN); };
  return Rect{at(r_.u0, r_.u1, i * s), at(r_.u0, r_.u1, (i + 1) * s), at(r_.v0, r_.v1, j * s), at(r_.v0, r_.v1, (j + 1) * s)};
}

std::size_t CurvedPieces::probe(int i, int j) {
  if (slot_.empty()) slot_.assign(std::size_t(kN + 1) * (kN + 1), -1);
  std::int32_t& k = slot_[std::size_t(i) * (kN + 1) + std::size_t(j)];
  if (k < 0) {
    const double u = r_.u0 + r_.du() * (double(i) / kN), v = r_.v0 + r_.dv() * (double(j) / kN);
    k = std::int32_t(p_.size());
    p_.push_back(sf_->point(u, v));
    n_.push_back(sf_->normal(u, v));
  }
  return std::size_t(k);
}

bool CurvedPieces::topFaces(const Vec3& x, double tol) {
  constexpr int h = kN / 2;
  for (int a = 0; a <= 2; ++a)
    for (int b = 0; b <= 2; ++b) {
      const std::size_t k = probe(a * h, b * h);
      if (glm::dot(n_[k], x - p_[k]) < -tol) return false;
    }
  return true;
}

double CurvedPieces::piece(int depth, int i, int j, const Vec3& x, const Vec3& n) {
  // Probe the piece: where every probe faces x from above x's horizon the contour integral is exact;
  // where none does the piece sends nothing to x (its facing part, if any, lies between probes and
  // is smaller than a probe cell); a piece across the terminator or the horizon is split. A piece at
  // depth d has its probes (corners, edge midpoints, centre) on the lattice of spacing
  // 2^-(kMaxSplits + 1), where the other pieces and the other points find them made.
  const int s = kN >> depth, h = s / 2;
  const double tol = 1e-12 * (1.0 + glm::length(x));
  int facing = 0;
  for (int a = 0; a <= 2; ++a)
    for (int b = 0; b <= 2; ++b) {
      const std::size_t k = probe(i * s + a * h, j * s + b * h);
      facing += glm::dot(n_[k], x - p_[k]) >= -tol && glm::dot(n, p_[k] - x) >= -tol ? 1 : 0;
    }
  if (facing == 0) return 0.0;
  const Rect r = rectOf(depth, i, j);
  if (facing == kProbe * kProbe) {
    const std::size_t id = std::size_t(((1 << (2 * depth)) - 1) / 3) + std::size_t(i) * (std::size_t(1) << depth) + std::size_t(j);
    if (outlineSlot_.empty()) outlineSlot_.assign(std::size_t(((1 << (2 * (kMaxSplits + 1))) - 1) / 3), -1);
    std::int32_t& o = outlineSlot_[id];
    if (o < 0) {
      o = std::int32_t(outlineCount_++);
      if (outlines_.size() < outlineCount_) outlines_.emplace_back();
      outline(*sf_, r, outlines_[std::size_t(o)]);  // (outline clears what an earlier rectangle left)
    }
    return contourFormFactor(x, n, outlines_[std::size_t(o)], true);  // clipped: chords may dip below the horizon
  }
  const std::size_t c = probe(i * s + h, j * s + h);
  const Vec3 d = x - p_[c];
  const double um = 0.5 * (r.u0 + r.u1), vm = 0.5 * (r.v0 + r.v1);
  if (depth >= kMaxSplits || sf_->jacobian(um, vm) * r.du() * r.dv() < kSmall * glm::dot(d, d)) return diskFormFactor(*sf_, r, x, n);
  double sum = 0.0;
  for (int k = 0; k < 4; ++k) sum += piece(depth + 1, 2 * i + (k & 1), 2 * j + ((k >> 1) & 1), x, n);
  return sum;
}

double insideFormFactor(const Surface& sf, const Rect& r, double u, double v, const Vec3& x, const Vec3& n) {
  // Around x the contour would enclose x itself (its projection wraps the zenith instead of the
  // band the piece fills), so the rectangle is cut 3 x 3 with x at the centre of the middle cell:
  // the eight outer cells hold x outside, the middle one is cut again, four times. The last middle
  // cell, (1/32)^2 of the rectangle, is left out: on a sphere it carries that share of F.
  double sum = 0.0, h = 0.25 * r.du(), k = 0.25 * r.dv();
  Rect c = r;
  for (int level = 0; level < 4; ++level, h *= 0.5, k *= 0.5) {
    const double us[4] = {c.u0, std::max(c.u0, u - h), std::min(c.u1, u + h), c.u1};
    const double vs[4] = {c.v0, std::max(c.v0, v - k), std::min(c.v1, v + k), c.v1};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if ((i != 1 || j != 1) && us[i + 1] > us[i] && vs[j + 1] > vs[j])
          sum += curvedFormFactor(sf, Rect{us[i], us[i + 1], vs[j], vs[j + 1]}, x, n);
    c = Rect{us[1], us[2], vs[1], vs[2]};
  }
  return sum;
}

void outline(const Surface& s, const Rect& r, std::vector<Vec3>& out) {
  out.clear();
  auto add = [&](const Vec3& p) {
    if (out.empty() || glm::length(p - out.back()) > 1e-12 * (1.0 + glm::length(p))) out.push_back(p);
  };
  // The u-edges keep the star map's polygon vertices.
  thread_local std::vector<double> us;  // (kept: outlines are made by the thousand)
  us.clear();
  const int nu = segments(s, true, r), nv = segments(s, false, r);
  for (int i = 0; i <= nu; ++i) us.push_back(r.u0 + r.du() * i / nu);
  for (double b : s.breaks())
    if (b > r.u0 && b < r.u1) us.push_back(b);
  std::sort(us.begin(), us.end());
  for (double u : us) add(s.point(u, r.v0));
  for (int j = 1; j <= nv; ++j) add(s.point(r.u1, r.v0 + r.dv() * j / nv));
  for (auto it = us.rbegin() + 1; it != us.rend(); ++it) add(s.point(*it, r.v1));
  for (int j = nv - 1; j >= 1; --j) add(s.point(r.u0, r.v0 + r.dv() * j / nv));
  while (out.size() > 1 && glm::length(out.front() - out.back()) <= 1e-12 * (1.0 + glm::length(out.back()))) out.pop_back();
  // Counter-clockwise about the front: polar maps run the other way round.
  Vec3 area(0.0);
  for (std::size_t i = 0; i < out.size(); ++i) area += glm::cross(out[i], out[(i + 1) % out.size()]);
  if (glm::dot(area, s.normal(0.5 * (r.u0 + r.u1), 0.5 * (r.v0 + r.v1))) < 0.0) std::reverse(out.begin(), out.end());
}

double contourFormFactor(const Vec3& x, const Vec3& n, const std::vector<Vec3>& pts, bool clip) {
  thread_local std::vector<Vec3> clipped;
  const std::vector<Vec3>* poly = &pts;
  if (clip) {
    // Sutherland-Hodgman against the horizon plane n . (p - x) >= 0.
    clipped.clear();
    const std::size_t m = pts.size();
    for (std::size_t i = 0; i < m; ++i) {
      const Vec3 &a = pts[i], &b = pts[(i + 1) % m];
      double da = glm::dot(n, a - x), db = glm::dot(n, b - x);
      if (da >= 0.0) clipped.push_back(a);
      if ((da >= 0.0) != (db >= 0.0)) clipped.push_back(a + (b - a) * (da / (da - db)));
    }
    poly = &clipped;
  }
  const std::vector<Vec3>& p = *poly;
  if (p.size() < 3) return 0.0;
  double sum = 0.0;
  Vec3 a = p.back() - x;
  double la = glm::length(a);
  for (const Vec3& q : p) {
    Vec3 b = q - x;
    double lb = glm::length(b);
    if (la > 0.0 && lb > 0.0) {
      Vec3 c = glm::cross(a, b);
      double cl = glm::length(c);
      if (cl > 0.0) sum += hr::edgeAngle(cl, glm::dot(a, b)) * glm::dot(n, c) / cl;
    }
    a = b, la = lb;
  }
  // A contour counter-clockwise about its front, seen from that front, runs clockwise about the
  // viewer's normal: the sum is negative; a positive one means x sees the back.
  return std::clamp(-sum / (2.0 * hr::kPi), 0.0, 1.0);
}

}  // namespace vision::detail
