// What the host reads of the extension's light: intensity toward a receiver and its bound over a
// cone (sending and the oracle), reflected power and exitant samples (the energy audit), radiance
// toward the eye and coefficient counts (display and inspection). All const and safe to call from
// many threads at once; every result is finite.
#include <glossy/bound.h>
#include <glossy/brdf.h>
#include <glossy/illumination_samples.h>
#include <glossy/spherical_geometry.h>

namespace glossy {

namespace {

bool hasHorizon(const IlluminationSamples::NodeLight& l) { return l.normal != Vec3(0.0); }

Rgb finiteOrZero(const Rgb& v) { return hr::allFinite(v) ? v : Rgb(0.0); }

/// Tetrahedron and spherical harmonics: the angle below which the basis cannot tell directions
/// apart (a vertex spacing; half a wavelength of the highest band). Radiance divides by a cosine no
/// smaller than the sine of it (see radiance()).
double resolutionAngle(const AnyDistribution& d) {
  if (const auto* t = std::get_if<TetraDistribution>(&d)) return std::acos(-1.0 / 3.0) / double(1 << t->level());
  if (const auto* s = std::get_if<ShDistribution>(&d)) return kPi / s->order();
  return 0.0;
}

/// A bound of one part's intensity within acos(cosHalfAngle) of unit axis.
Rgb boundOfPart(const IlluminationSamples::NodeLight* l, const Vec3& axis, double cosHalfAngle) {
  Cap cone = Cap::cone(l->frame.toLocal(axis), cosHalfAngle);
  if (cone.whole()) return l->peak;
  // A cone wholly below a planar node's horizon sees nothing of it (angle to the normal >= 90 + half).
  if (hasHorizon(*l) && cone.cosR >= 0.0 && glm::dot(l->normal, axis) <= -(cone.sinR + 1e-9) * glm::length(axis))
    return Rgb(0.0);
  return glm::max(Rgb(0.0), glm::min(l->peak, boundOver(l->dist, cone)));
}

/// The bound of a light's parts summed: a sum never exceeds the sum of its terms' bounds.
Rgb boundOf(const IlluminationSamples::NodeLight* l, const Vec3& axis, double cosHalfAngle) {
  if (!l) return Rgb(0.0);
  Rgb b = boundOfPart(l, axis, cosHalfAngle);
  for (const auto& m : l->more) b += boundOfPart(&m, axis, cosHalfAngle);
  return b;
}

}  // namespace

/// A light's intensity toward unit dir, W/sr: nothing below a planar node's horizon, never negative
/// (spherical harmonics ring below zero around a lobe: none of that is sent).
hr::Rgb IlluminationSamples::intensityOfPart(const NodeLight& l, const hr::Vec3& dir) {
  if (hasHorizon(l) && !(glm::dot(l.normal, dir) > 0.0)) return Rgb(0.0);
  return finiteOrZero(glm::max(Rgb(0.0), eval(l.dist, l.frame.toLocal(dir))));
}

hr::Rgb IlluminationSamples::intensityOf(const NodeLight* l, const hr::Vec3& dir) {
  if (!l) return Rgb(0.0);
  Rgb sum = intensityOfPart(*l, dir);
  for (const NodeLight& m : l->more) sum += intensityOfPart(m, dir);
  return sum;
}

hr::Rgb IlluminationSamples::intensity(hr::NodeId node, const hr::Vec3& dir) const { return intensityOf(light(node), dir); }

hr::Rgb IlluminationSamples::intensityBound(hr::NodeId node, const hr::Vec3& axis, double cosHalfAngle) const {
  return boundOf(light(node), axis, cosHalfAngle);
}

hr::Rgb IlluminationSamples::unshotIntensity(hr::NodeId node, const hr::Vec3& dir) const {
  return intensityOf(unshotLight(node), dir);
}

hr::Rgb IlluminationSamples::unshotIntensityBound(hr::NodeId node, const hr::Vec3& axis, double cosHalfAngle) const {
  return boundOf(unshotLight(node), axis, cosHalfAngle);
}

hr::Rgb IlluminationSamples::reflectedPower(hr::NodeId leaf) const {
  const NodeLight* l = light(leaf);
  if (!l) return Rgb(0.0);
  if (std::holds_alternative<HaarDistribution>(l->dist) && l->more.empty()) return l->power;
  // Fixed bases: the integral of what intensity() returns (clamped at zero, nothing below the
  // horizon), by the midpoint rule on 64 x 128 cells of equal solid angle over the hemisphere.
  Vec3 u, v, n = hasHorizon(*l) ? l->normal : Vec3(0, 0, 1);
  orthonormalBasis(n, u, v);
  const int NZ = hasHorizon(*l) ? 64 : 128, NP = 128;
  Rgb sum(0.0);
  for (int i = 0; i < NZ; ++i) {
    double z = hasHorizon(*l) ? (i + 0.5) / NZ : 1.0 - 2.0 * (i + 0.5) / NZ;
    double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    for (int j = 0; j < NP; ++j) {
      double phi = 2.0 * kPi * (j + 0.5) / NP;
      sum += intensity(leaf, z * n + r * (std::cos(phi) * u + std::sin(phi) * v));
    }
  }
  return sum * ((hasHorizon(*l) ? 2.0 : 4.0) * kPi / (NZ * NP));
}

hr::Rgb IlluminationSamples::sampleExitant(hr::NodeId leaf, double u1, double u2, hr::Vec3& dir) const {
  const NodeLight* l = light(leaf);
  dir = l && hasHorizon(*l) ? l->normal : Vec3(0, 0, 1);
  if (!l) return Rgb(0.0);
  u1 = glm::clamp(u1, 0.0, std::nextafter(1.0, 0.0));
  u2 = glm::clamp(u2, 0.0, std::nextafter(1.0, 0.0));
  if (const auto* h = std::get_if<HaarDistribution>(&l->dist)) {
    // Descend by power (a cell's mean times its solid angle; channels summed), reusing u1, then a
    // uniform direction in the leaf cell: the weight is the cell's value over the density.
    const auto& nodes = h->nodes();
    auto mass = [&](std::uint32_t i, const FaceTri& t) {
      const float* v = nodes[i].rgb;
      return (double(v[0]) + double(v[1]) + double(v[2])) * t.solidAngle();
    };
    double p = 1.0;
    auto choose = [&](const double* m, int count) {
      double total = 0.0;
      for (int k = 0; k < count; ++k) total += m[k];
      if (!(total > 0.0)) return -1;
      double x = u1 * total, before = 0.0, acc = 0.0;
      int pick = -1;
      for (int k = 0; k < count; ++k) {
        if (!(m[k] > 0.0)) continue;  // never land on an empty cell, even by rounding
        pick = k;
        before = acc;
        acc += m[k];
        if (x < acc) break;
      }
      u1 = glm::clamp((x - before) / m[pick], 0.0, std::nextafter(1.0, 0.0));
      p *= m[pick] / total;
      return pick;
    };
    double m[8];
    for (int f = 0; f < 8; ++f) m[f] = mass(std::uint32_t(f), octaRoot(f));
    int f = choose(m, 8);
    if (f < 0) return Rgb(0.0);
    std::uint32_t i = std::uint32_t(f);
    FaceTri t = octaRoot(f);
    while (nodes[i].child != 0) {
      for (int k = 0; k < 4; ++k) m[k] = mass(nodes[i].child + std::uint32_t(k), t.child(k));
      int k = choose(m, 4);
      if (k < 0) return Rgb(0.0);
      i = nodes[i].child + std::uint32_t(k);
      t = t.child(k);
    }
    Vec3 local = sampleTriangle(t.dir(0), t.dir(1), t.dir(2), u1, u2);
    dir = l->frame.toWorld(local);
    const float* v = nodes[i].rgb;
    return finiteOrZero(Rgb(v[0], v[1], v[2]) * (t.solidAngle() / p));
  }
  // Fixed bases: uniform over the hemisphere above the leaf (the sphere without a horizon).
  Vec3 u, v, n = dir;
  orthonormalBasis(n, u, v);
  double z = hasHorizon(*l) ? 1.0 - u1 : 1.0 - 2.0 * u1, r = std::sqrt(std::max(0.0, 1.0 - z * z));
  double phi = 2.0 * kPi * u2;
  dir = z * n + r * (std::cos(phi) * u + std::sin(phi) * v);
  return intensity(leaf, dir) * ((hasHorizon(*l) ? 2.0 : 4.0) * kPi);
}

// Without a point (display vertices, the viewer) a leaf shows its stored distribution alone, as the
// paper: the shown light costs a cell integral per evaluation (36 us against 0.5 us per vertex in
// bench_display) and a sharp highlight sampled at vertices only aliases. With a point (still images)
// the shown light sharpens it (shown_light.h).
hr::Rgb IlluminationSamples::radiance(hr::NodeId leaf, const hr::Vec3& toEye) const {
  return radianceAt(leaf, toEye, Vec3(0.0), nullptr);
}

hr::Rgb IlluminationSamples::radiance(hr::NodeId leaf, const hr::Vec3& toEye, const hr::Vec3& normal) const {
  return radianceAt(leaf, toEye, normal, nullptr);
}

hr::Rgb IlluminationSamples::radiance(hr::NodeId leaf, const hr::Vec3& toEye, const hr::Vec3& normal,
                                      const hr::Vec3& at) const {
  return radianceAt(leaf, toEye, normal, &at);
}

namespace {

/// A Haar leaf's radiance toward unit `seen` (W/(m^2 sr)): its cell's mean, less that cell's mean of
/// the shown samples' lobes when it keeps some (the caller adds their exact reflection instead).
Rgb haarRadiance(const IlluminationSamples::NodeLight& l, const HaarDistribution& h, const Vec3& seen, bool shown) {
  if (!(glm::dot(l.normal, seen) > 0.0)) return Rgb(0.0);
  // L = I / (A cos): with I a cell mean, divide by the cell's mean cosine (its projected solid
  // angle over its solid angle), not the cosine at the eye. That is the radiance whose intensity
  // has exactly that mean, and it stays finite at grazing: every cell above the horizon (the
  // local frame's equator) has a positive mean cosine.
  FaceTri cell;
  int level = 0;
  std::uint64_t index = 0;
  const std::uint32_t i = h.locate(l.frame.toLocal(seen), &cell, &level, &index);
  const Vec3 a = cell.dir(0), b = cell.dir(1), c = cell.dir(2);
  const double omega = solidAngle(a, b, c), meanCos = omega > 0.0 ? projectedSolidAngle(a, b, c, Vec3(0, 0, 1)) / omega : 0.0;
  if (!(meanCos > 0.0)) return Rgb(0.0);
  const float* v = h.nodes()[i].rgb;
  Rgb mean(v[0], v[1], v[2]);
  if (shown) mean -= shownCellMean(*l.shown, l.frame, l.area, level, index, omega);
  return mean / (l.area * meanCos);
}

}  // namespace

hr::Rgb IlluminationSamples::radianceAt(hr::NodeId leaf, const hr::Vec3& toEye, const hr::Vec3& normal,
                                        const hr::Vec3* at) const {
  const NodeLight* l = light(leaf);
  if (!l || !hasHorizon(*l) || !(l->area > 0.0)) return Rgb(0.0);
  const bool turned = hr::allFinite(normal) && std::abs(glm::length(normal) - 1.0) < 1e-6 &&
                      glm::dot(normal, l->normal) < 1.0 - 1e-12;
  const Vec3 n = turned ? normal : l->normal;
  if (!(glm::dot(n, toEye) > 0.0)) return Rgb(0.0);
  // The leaf reflected its incident light about its one normal. A point of a curved surface mirrors
  // the same incident light about its own: the light it sends toward the eye came from in, which the
  // leaf mirrored toward seen. Turning the lookup by the normal's turn alone would move a highlight
  // half as far as the surface turns it (a mirror turns reflections by twice the normal's angle).
  const Vec3 seen = turned ? mirror(mirror(toEye, n), l->normal) : toEye;
  if (const auto* h = std::get_if<HaarDistribution>(&l->dist)) {
    const bool shown = l->shown && at && hr::allFinite(*at);
    Rgb L = haarRadiance(*l, *h, seen, shown);
    if (shown) L += shownRadiance(*l->shown, *at, n, toEye);
    return finiteOrZero(glm::max(L, Rgb(0.0)));
  }
  // Fixed bases hold directions only to their resolution, so the cosine they imply is not known
  // below the sine of that angle: divide by no less (sin 6.8 deg at tetra level 3, sin 11.25 deg at SH order 8).
  double floor = std::sin(0.5 * resolutionAngle(l->dist));
  return finiteOrZero(intensity(leaf, seen) / (l->area * std::max(glm::dot(l->normal, seen), floor)));
}

std::size_t IlluminationSamples::coefficients(hr::NodeId leaf) const {
  const NodeLight* l = light(leaf);
  return l ? l->totalCoefficients() : 0;
}

}  // namespace glossy
