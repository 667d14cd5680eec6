// The extension's share of a sender's unshot light (hr/extension.h; additive: the host sends its own
// Lambertian light as before and adds this share wherever it reads a sender). As on the BRIGHT-like
// host: toward a far element receiver the extension's mean intensity over the receiver's directions
// becomes the radiosity pi I / (A cos) that the form factor turns into irradiance; toward a near one
// it carries the flux the distribution sends into the receiver's solid angle, Phi = mean I x Omega,
// as the radiosity pi Phi / (A Omega_proj): exact for a cosine lobe, and never the value toward the
// receiver's centre spread over a wide receiver (which made light out of nothing against narrow
// lobes). A curved sender has no one plane that turns the flux into a radiosity (its centre's
// horizon cut a receiver its edge still sees, and the floor under a shiny sphere got tens of times
// the light sent: the solve oscillated), so toward any receiver it delivers the flux alone,
// Phi / A_r. A part of a leaf sends the leaf's light scaled by its share of the leaf's area.
#include <algorithm>
#include <cmath>
#include <limits>

#include "state.h"

namespace vision::detail {
namespace {

/// (r_s + r_r) / d below which the receiver counts as far.
constexpr double kFarField = 0.25;

/// Solid angle of a convex spherical polygon of unit directions (Van Oosterom and Strackee per fan
/// triangle).
double solidAngle(const std::vector<Vec3>& d) {
  double sum = 0.0;
  for (std::size_t k = 1; k + 1 < d.size(); ++k) {
    double num = std::abs(glm::dot(d[0], glm::cross(d[k], d[k + 1])));
    double den = 1.0 + glm::dot(d[0], d[k]) + glm::dot(d[k], d[k + 1]) + glm::dot(d[k + 1], d[0]);
    sum += 2.0 * std::atan2(num, den);
  }
  return sum;
}

/// The receiver's corners (a pole or a disk's centre collapses two), counter-clockwise about its front.
void corners(const Surface& sf, const Rect& r, std::vector<Vec3>& out) {
  out.clear();
  for (auto [u, v] : {std::pair{r.u0, r.v0}, {r.u1, r.v0}, {r.u1, r.v1}, {r.u0, r.v1}}) {
    Vec3 p = sf.point(u, v);
    if (out.empty() || glm::length(p - out.back()) > 1e-12 * (1.0 + glm::length(p))) out.push_back(p);
  }
  if (out.size() > 1 && glm::length(out.front() - out.back()) <= 1e-12 * (1.0 + glm::length(out.back()))) out.pop_back();
  Vec3 area(0.0);
  for (std::size_t i = 0; i < out.size(); ++i) area += glm::cross(out[i], out[(i + 1) % out.size()]);
  if (glm::dot(area, sf.normal(0.5 * (r.u0 + r.u1), 0.5 * (r.v0 + r.v1))) < 0.0) std::reverse(out.begin(), out.end());
}

Vec3 senderNormal(const State& s, const Sender& x) {
  const Surface& sf = s.h.surfaces()[x.e->surface];
  return sf.planar() ? x.g.coneAxis : x.g.normal;
}

}  // namespace

void extensionSender(const State& s, Sender& x) {
  if (!s.ext) return;
  if (x.cluster != hr::kNone) {
    x.node = NodeView::cluster(x.cluster);
    x.owned = s.ownedCluster[x.cluster] != 0;
  } else {
    x.node = hr::NodeId{x.e->id};
    x.owned = s.ownedSurface[x.e->surface] != 0;
    x.share = x.part && x.e->g.area > 0.0 ? x.g.area / x.e->g.area : 1.0;
  }
  if (x.owned) x.X = s.ext->unshotPower(x.node) * x.share;
}

Rgb extensionIntensity(const State& s, const Sender& x, const Vec3& dir) {
  if (!x.owned || x.X == Rgb(0.0)) return Rgb(0.0);
  return s.ext->unshotIntensity(x.node, dir) * x.share;
}

Rgb extensionIrradiance(const State& s, const Sender& x, const Element& r, double F) {
  if (!x.owned || x.X == Rgb(0.0) || x.cluster != hr::kNone || !(x.g.area > 0.0) || !(F > 0.0)) return Rgb(0.0);
  const Vec3 n = senderNormal(s, x), from = x.g.center;
  thread_local std::vector<Vec3> pts, dirs;
  corners(s.h.surfaces()[r.surface], r.rect, pts);
  dirs.clear();
  for (const Vec3& p : pts) {
    Vec3 d = p - from;
    double len = glm::length(d);
    if (!(len > 0.0)) return Rgb(0.0);  // a receiver corner at the sender's centre: no solid angle
    dirs.push_back(d / len);
  }
  if (dirs.size() < 3) return Rgb(0.0);
  const Rgb I = s.ext->unshotMeanIntensity(x.node, dirs) * x.share;
  Rgb v(0.0);
  const double d = glm::length(r.g.center - from);
  if (!s.h.surfaces()[x.e->surface].planar()) {
    const Rgb E = r.g.area > 0.0 ? I * solidAngle(dirs) / r.g.area : Rgb(0.0);
    return hr::allFinite(E) ? glm::max(E, Rgb(0.0)) : Rgb(0.0);
  }
  if (d > 0.0 && (x.g.radius + r.g.radius) / d <= kFarField) {
    const double c = glm::dot(n, (r.g.center - from) / d);
    if (c > 1e-6) v = hr::kPi * I / (x.g.area * c);
  } else {
    const double omega = solidAngle(dirs), projected = hr::kPi * contourFormFactor(from, n, pts, true);
    if (omega > 0.0 && projected > 0.0) v = hr::kPi * I * omega / (x.g.area * projected);
  }
  return hr::allFinite(v) ? glm::max(v, Rgb(0.0)) * F : Rgb(0.0);
}

double extensionGap(const State& s, const Sender& x, const Geometry& r, const KernelBounds& kb, bool coarse) {
  if (!x.owned || x.X == Rgb(0.0)) return 0.0;
  if (kb.overlap || !(kb.rmin2 > 0.0)) return std::numeric_limits<double>::infinity();
  // The power received is about A_r I cos_r / r^2: at most with the bound of I over the cone of
  // directions toward the receiver (or over all directions), at least with the least of I toward the
  // receiver's centre and its box's corners (not a bound, as on the other host: exitant light is
  // approximate anyway, paper section 3.1).
  const double cosHalf = coarse || kb.beta >= 0.5 * hr::kPi ? -1.0 : std::cos(kb.beta);
  const double hi = hr::luminance(s.ext->unshotIntensityBound(x.node, kb.axis, cosHalf)) * x.share;
  const double upper = r.area * hi * kb.rHi / kb.rmin2;
  if (coarse) return upper;
  double lo = std::numeric_limits<double>::infinity();
  auto toward = [&](const Vec3& p) {
    Vec3 d = p - x.g.center;
    double len = glm::length(d);
    lo = std::min(lo, len > 0.0 ? hr::luminance(extensionIntensity(s, x, d / len)) : 0.0);
  };
  toward(r.center);
  for (int k = 0; k < 8; ++k)
    toward(Vec3((k & 1) ? r.box.hi.x : r.box.lo.x, (k & 2) ? r.box.hi.y : r.box.lo.y, (k & 4) ? r.box.hi.z : r.box.lo.z));
  return std::max(0.0, upper - r.area * lo * kb.rLo / kb.rmax2);
}

double extensionUnshot(const State& s) {
  if (!s.ext) return 0.0;
  double sum = 0.0;  // surface order: the same for any thread count
  for (const Element& r : s.h.roots())
    if (s.ownedSurface[r.surface]) sum += hr::luminance(s.ext->unshotPower(hr::NodeId{r.id}));
  return sum;
}

}  // namespace vision::detail
