// Element geometry in parameter space: the measure of a rectangle (area, centroid, spread by
// Gauss-Legendre quadrature; box and normal cone from a grid of samples widened by how far the
// surface can bulge between them) and the rule that splits it.
#include <vision/hierarchy.h>

#include <algorithm>
#include <cmath>

namespace vision {
namespace {

constexpr double kGauss[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281, 0.9305681557970263};
constexpr double kWeight[4] = {0.1739274225837472, 0.3260725774162528, 0.3260725774162528, 0.1739274225837472};

double angleBetween(const Vec3& a, const Vec3& b) {
  double la = glm::length(a), lb = glm::length(b);
  if (!(la > 0.0) || !(lb > 0.0)) return 0.0;
  return std::acos(std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0));
}

/// Samples per parameter direction: enough that the surface turns at most about 22 degrees between
/// two of them (a margin covers the bulge in between).
void gridSize(const Surface& s, const Rect& r, int& mu, int& mv) {
  mu = mv = 1;
  if (s.straightEdges()) return;
  const double turnU = 2.0 * hr::kPi * r.du();
  mu = std::clamp(int(std::ceil(turnU / (hr::kPi / 8.0))), 2, 16);
  if (s.kind == SurfaceKind::Sphere) {
    double span = std::acos(std::clamp(1.0 - 2.0 * r.v1, -1.0, 1.0)) - std::acos(std::clamp(1.0 - 2.0 * r.v0, -1.0, 1.0));
    mv = std::clamp(int(std::ceil(std::abs(span) / (hr::kPi / 8.0))), 2, 16);
  } else {
    mv = 2;  // annulus radii and frustum generators are straight
  }
}

/// How far a curve through samples p[0..n) can leave its chords: per segment, half its length times
/// the tangent of half the turn at its ends (a circular arc's sagitta is half of that).
double bulge(const Vec3* p, int n) {
  double m = 0.0;
  for (int i = 0; i + 1 < n; ++i) {
    Vec3 c = p[i + 1] - p[i];
    double turn = 0.0;
    if (i > 0) turn = std::max(turn, angleBetween(p[i] - p[i - 1], c));
    if (i + 2 < n) turn = std::max(turn, angleBetween(c, p[i + 2] - p[i + 1]));
    m = std::max(m, 0.5 * glm::length(c) * std::tan(0.5 * std::min(turn, 2.8)));
  }
  return m;
}

}  // namespace

Geometry measure(const Surface& s, const Rect& r) {
  Geometry g;
  const double pa = r.du() * r.dv();
  Vec3 nsum(0.0), csum(0.0);
  double area = 0.0, second = 0.0;
  const Vec3 mid = s.point(0.5 * (r.u0 + r.u1), 0.5 * (r.v0 + r.v1));
  glm::dmat3 outer(0.0);  // about mid, for a flat sender's shape
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      double u = r.u0 + kGauss[i] * r.du(), v = r.v0 + kGauss[j] * r.dv();
      double w = kWeight[i] * kWeight[j] * pa * s.jacobian(u, v);
      Vec3 p = s.point(u, v);
      area += w, csum += w * p, nsum += w * s.normal(u, v), second += w * glm::dot(p, p);
      outer += w * glm::outerProduct(p - mid, p - mid);
    }
  g.area = area;
  g.center = area > 0.0 ? csum / area : mid;
  g.spread2 = area > 0.0 ? std::max(0.0, second / area - glm::dot(g.center, g.center)) : 0.0;
  double nl = glm::length(nsum);
  g.normal = nl > 0.0 ? nsum / nl : Vec3(0.0);
  if (s.planar() && area > 0.0 && g.normal != Vec3(0.0)) {
    const double vm = 0.5 * (r.v0 + r.v1);  // the u direction names a square element's axis
    g.shape = hr::rectangleOfMoments(outer / area - glm::outerProduct(g.center - mid, g.center - mid),
                                     g.normal, s.point(r.u1, vm) - s.point(r.u0, vm));
  }

  // Box, radius and cone from a grid (planar kinds: the outline's corners and polygon vertices).
  int mu, mv;
  gridSize(s, r, mu, mv);
  std::vector<double> us;
  for (int i = 0; i <= mu; ++i) us.push_back(r.u0 + r.du() * i / mu);
  for (double b : s.breaks())
    if (b > r.u0 && b < r.u1) us.push_back(b);
  std::sort(us.begin(), us.end());
  const int nu = int(us.size()), nv = mv + 1;
  std::vector<Vec3> pts(std::size_t(nu) * nv), nrm(pts.size());
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      double v = r.v0 + r.dv() * j / mv;
      pts[std::size_t(j) * nu + i] = s.point(us[i], v);
      nrm[std::size_t(j) * nu + i] = s.normal(us[i], v);
    }
  double margin = 0.0, turn = 0.0;
  std::vector<Vec3> line;
  for (int j = 0; j < nv; ++j) margin = std::max(margin, bulge(&pts[std::size_t(j) * nu], nu));
  double marginV = 0.0;
  for (int i = 0; i < nu; ++i) {
    line.clear();
    for (int j = 0; j < nv; ++j) line.push_back(pts[std::size_t(j) * nu + i]);
    marginV = std::max(marginV, bulge(line.data(), nv));
  }
  margin += marginV;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const std::size_t k = std::size_t(j) * nu + i;
      g.box.grow(pts[k]);
      g.radius = std::max(g.radius, glm::length(pts[k] - g.center));
      if (i + 1 < nu) turn = std::max(turn, angleBetween(nrm[k], nrm[k + 1]));
      if (j + 1 < nv) turn = std::max(turn, angleBetween(nrm[k], nrm[k + nu]));
    }
  g.box.lo -= Vec3(margin), g.box.hi += Vec3(margin);
  g.radius += margin;
  if (s.planar()) {
    g.coneAxis = s.normal(0.5, 0.5);
    g.coneAngle = 0.0;
  } else if (nl > 1e-3 * area) {
    g.coneAxis = g.normal;
    double a = 0.0;
    for (const Vec3& n : nrm) a = std::max(a, angleBetween(g.coneAxis, n));
    g.coneAngle = std::min(hr::kPi, a + 0.5 * turn);
  } else {
    g.coneAxis = Vec3(0.0, 0.0, 1.0);
    g.coneAngle = hr::kPi;
  }
  return g;
}

Split splitOf(const Surface& s, const Rect& r) {
  // World lengths of the rectangle's two mid-lines, each as a polyline of four chords.
  auto length = [&](bool alongU) {
    double L = 0.0, um = 0.5 * (r.u0 + r.u1), vm = 0.5 * (r.v0 + r.v1);
    Vec3 prev = alongU ? s.point(r.u0, vm) : s.point(um, r.v0);
    for (int k = 1; k <= 4; ++k) {
      Vec3 p = alongU ? s.point(r.u0 + r.du() * k / 4, vm) : s.point(um, r.v0 + r.dv() * k / 4);
      L += glm::length(p - prev);
      prev = p;
    }
    return L;
  };
  const double Lu = length(true), Lv = length(false), um = 0.5 * (r.u0 + r.u1), vm = 0.5 * (r.v0 + r.v1);
  Split sp;
  if (Lu > 2.0 * Lv) {
    sp.kids[0] = {r.u0, um, r.v0, r.v1};
    sp.kids[1] = {um, r.u1, r.v0, r.v1};
    sp.count = 2, sp.levelStep = 1;
  } else if (Lv > 2.0 * Lu) {
    sp.kids[0] = {r.u0, r.u1, r.v0, vm};
    sp.kids[1] = {r.u0, r.u1, vm, r.v1};
    sp.count = 2, sp.levelStep = 1;
  } else {
    sp.kids[0] = {r.u0, um, r.v0, vm};
    sp.kids[1] = {um, r.u1, r.v0, vm};
    sp.kids[2] = {um, r.u1, vm, r.v1};
    sp.kids[3] = {r.u0, um, vm, r.v1};
    sp.count = 4, sp.levelStep = 2;
  }
  return sp;
}

void Hierarchy::subdivide(Element& e) const {
  if (e.nkids) return;
  const Surface& s = surfaces_[e.surface];
  Split sp = splitOf(s, e.rect);
  e.kids = std::make_unique<Element[]>(std::size_t(sp.count));
  for (int k = 0; k < sp.count; ++k) {
    Element& c = e.kids[k];
    c.rect = sp.kids[k];
    c.surface = e.surface;
    c.level = std::uint16_t(e.level + sp.levelStep);
    c.g = measure(s, c.rect);
    // A new child starts with its parent's light, so splitting does not change the solution.
    c.B = e.B, c.U = e.U, c.Etot = e.Etot;
    c.P = c.g.area * c.U;
  }
  e.nkids = std::uint8_t(sp.count);
}

}  // namespace vision
