// The extension's light over a receiver: the mean of a node's exitant intensity over a convex
// spherical polygon (the receiver's corners seen from the node). A link gives its whole receiver one
// value; taking it toward a few points of a receiver that a narrow lobe crosses under-delivered in a
// consistent sense (a spot on a wall came out 7 % dark), so the Haar tree is integrated exactly over
// the polygon: cells inside count whole at their mean, leaf cells on its border are clipped to it.
// Tetrahedron and SH distributions are smooth at their resolution and are averaged over a fixed grid
// of directions uniform in each triangle of the polygon.
#include <glossy/illumination_samples.h>
#include <glossy/spherical_geometry.h>

namespace glossy {
namespace {

struct PolygonRegion {
  SphericalPolygon poly;
  Vec3 inward[8];
  Cap cap;

  explicit PolygonRegion(std::span<const Vec3> corners) {
    poly.n = 0;
    Vec3 c(0.0);
    for (const Vec3& d : corners) {
      if (poly.n < 8) poly.v[poly.n++] = glm::normalize(d);
      c += glm::normalize(d);
    }
    c = glm::length(c) > 0.0 ? glm::normalize(c) : Vec3(0, 0, 1);
    for (int i = 0; i < poly.n; ++i) {
      Vec3 m = glm::cross(poly.v[i], poly.v[(i + 1) % poly.n]);
      inward[i] = glm::dot(m, c) < 0.0 ? -m : m;
    }
    cap.centre = c;
    cap.cosR = 1.0;
    for (int i = 0; i < poly.n; ++i) cap.cosR = std::min(cap.cosR, glm::dot(c, poly.v[i]));
    cap.sinR = std::sqrt(std::max(0.0, 1.0 - cap.cosR * cap.cosR));
  }
  bool inside(const Vec3& d) const {
    for (int i = 0; i < poly.n; ++i)
      if (glm::dot(inward[i], d) < 0.0) return false;
    return true;
  }
};

/// The integral (W) of a Haar distribution over the region, by descent.
Rgb haarIntegral(const HaarDistribution& h, std::uint32_t i, const FaceTri& t, const PolygonRegion& r) {
  if (!Cap::around(t).overlaps(r.cap)) return Rgb(0.0);
  const auto& node = h.nodes()[i];
  const Rgb value(node.rgb[0], node.rgb[1], node.rgb[2]);
  if (r.inside(t.dir(0)) && r.inside(t.dir(1)) && r.inside(t.dir(2))) return value * t.solidAngle();
  if (node.child == 0) {
    SphericalPolygon piece = SphericalPolygon::triangle(t.dir(0), t.dir(1), t.dir(2));
    for (int k = 0; k < r.poly.n; ++k) piece.clip(r.inward[k]);
    return piece.n >= 3 ? value * piece.area() : Rgb(0.0);
  }
  Rgb sum(0.0);
  for (int k = 0; k < 4; ++k) sum += haarIntegral(h, node.child + std::uint32_t(k), t.child(k), r);
  return sum;
}

}  // namespace

hr::Rgb IlluminationSamples::meanIntensity(hr::NodeId node, std::span<const hr::Vec3> polygon) const {
  return meanIntensityOf(light(node), polygon);
}

hr::Rgb IlluminationSamples::unshotMeanIntensity(hr::NodeId node, std::span<const hr::Vec3> polygon) const {
  return meanIntensityOf(unshotLight(node), polygon);
}

hr::Rgb IlluminationSamples::meanIntensityOf(const NodeLight* l, std::span<const hr::Vec3> polygon) {
  if (!l || polygon.size() < 3) return Rgb(0.0);
  Vec3 local[8];
  std::size_t n = std::min<std::size_t>(polygon.size(), 8);
  for (std::size_t k = 0; k < n; ++k) local[k] = l->frame.toLocal(polygon[k]);
  PolygonRegion region(std::span<const Vec3>(local, n));
  const double area = region.poly.area();
  if (!(area > 1e-14)) {
    Vec3 c(0.0);
    for (std::size_t k = 0; k < polygon.size(); ++k) c += polygon[k];
    return glm::length(c) > 0.0 ? intensityOf(l, glm::normalize(c)) : Rgb(0.0);
  }
  Rgb sum(0.0);
  if (const auto* h = std::get_if<HaarDistribution>(&l->dist)) {
    // A planar node's tree is in its own frame, whose lower octants are empty: nothing is sent below
    // its plane, as intensity() says.
    for (int f = 0; f < 8; ++f) sum += haarIntegral(*h, std::uint32_t(f), octaRoot(f), region);
    Rgb mean = sum / area;
    return hr::allFinite(mean) ? glm::max(mean, Rgb(0.0)) : Rgb(0.0);
  }
  // Fixed bases: a 4 x 4 grid of directions uniform over each triangle of the polygon's fan.
  const Vec3& a = polygon[0];
  for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
    const Vec3 b = polygon[k], c = polygon[k + 1];
    const double w = solidAngle(glm::normalize(a), glm::normalize(b), glm::normalize(c));
    Rgb part(0.0);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        part += intensityOf(l, sampleTriangle(glm::normalize(a), glm::normalize(b), glm::normalize(c), (i + 0.5) / 4, (j + 0.5) / 4));
    sum += part * (w / 16.0);
  }
  Rgb mean = sum / area;
  return hr::allFinite(mean) ? glm::max(mean, Rgb(0.0)) : Rgb(0.0);
}

}  // namespace glossy
