// The extension's light over a receiver: the mean of a node's exitant intensity over a convex
// spherical polygon (the receiver's corners seen from the node). A link gives its whole receiver one
// value; taking it toward a few points of a receiver that a narrow lobe crosses under-delivered in a
// consistent sense (a spot on a wall came out 7 % dark), so the Haar tree is integrated exactly over
// the polygon: cells inside count whole at their mean, leaf cells on its border are clipped to it.
// Tetrahedron and SH distributions are smooth at their resolution and are averaged over a fixed grid
// of directions uniform in each triangle of the polygon.
#include <glossy/cell_rules.h>
#include <glossy/illumination_samples.h>
#include <glossy/spherical_geometry.h>

namespace glossy {
namespace {

struct PolygonRegion {
  SphericalPolygon poly;
  Vec3 inward[8];
  Cap cap;
  double area = 0.0;

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
    area = poly.area();
  }
  /// The planes (bit i: edge i) with d on their inner side.
  unsigned insideOf(const Vec3& d) const {
    unsigned bits = 0;
    for (int i = 0; i < poly.n; ++i) bits |= glm::dot(inward[i], d) >= 0.0 ? 1u << i : 0u;
    return bits;
  }
};

/// How the region lies against a cell, by the planes of the cell's edges (m: inward normals, of the
/// planar corners or their directions alike: only signs are read): outside when all its corners are
/// strictly beyond one plane (both are convex and within a hemisphere, so they share no direction),
/// within when all are on the inner side of every plane.
enum class Side { Outside, Within, Straddles };
Side sideOf(const PolygonRegion& r, const Vec3 m[3]) {
  bool within = true;
  for (int k = 0; k < 3; ++k) {
    int behind = 0;
    for (int i = 0; i < r.poly.n; ++i) behind += glm::dot(m[k], r.poly.v[i]) < 0.0 ? 1 : 0;
    if (behind == r.poly.n) return Side::Outside;
    within = within && behind == 0;
  }
  return within ? Side::Within : Side::Straddles;
}

/// The integral (W) of a Haar distribution over the region, by descent (t: the cell's planar corners;
/// face, level and index name it for the tables of hull caps and solid angles). The trees are
/// non-negative (exact means of non-negative lobes), so a zero cell has only zeros below it. Corner
/// tests read the planar corners (a direction's sign against a plane is its planar point's); only a
/// leaf cell that straddles the region's border is clipped on the sphere.
Rgb haarIntegral(const HaarDistribution& h, std::uint32_t i, const FaceTri& t, int face, int level, std::uint64_t index,
                 const PolygonRegion& r) {
  const auto& node = h.nodes()[i];
  if (node.rgb[0] == 0.0f && node.rgb[1] == 0.0f && node.rgb[2] == 0.0f) return Rgb(0.0);
  const CellGeometry g(t, face, level, index);
  if (!g.cap.overlaps(r.cap)) return Rgb(0.0);
  const Rgb value(node.rgb[0], node.rgb[1], node.rgb[2]);
  const unsigned all = (1u << r.poly.n) - 1u, in = r.insideOf(t.p[0]) & r.insideOf(t.p[1]) & r.insideOf(t.p[2]);
  if (in == all) return value * g.solidAngle(t);
  Vec3 m[3];
  insideNormals(t.p[0], t.p[1], t.p[2], m);
  const Side side = sideOf(r, m);
  if (side == Side::Outside) return Rgb(0.0);
  if (node.child == 0) {
    // A region within the leaf cell is all of it; otherwise the cell clipped to the region.
    if (side == Side::Within) return value * r.area;
    // Planes with the whole cell inside leave it as it is: only the others clip.
    SphericalPolygon piece = SphericalPolygon::triangle(t.dir(0), t.dir(1), t.dir(2));
    for (int k = 0; k < r.poly.n; ++k)
      if (!(in >> k & 1u)) piece.clip(r.inward[k]);
    return piece.n >= 3 ? value * piece.area() : Rgb(0.0);
  }
  Rgb sum(0.0);
  for (int k = 0; k < 4; ++k)
    sum += haarIntegral(h, node.child + std::uint32_t(k), t.child(k), face, level + 1, 4 * index + std::uint64_t(k), r);
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
  // A node mixing bases: the mean of a sum is the sum of the parts' means.
  Rgb sum = meanIntensityOfPart(*l, polygon);
  for (const NodeLight& m : l->more) sum += meanIntensityOfPart(m, polygon);
  return sum;
}

hr::Rgb IlluminationSamples::meanIntensityOfPart(const NodeLight& one, std::span<const hr::Vec3> polygon) {
  const NodeLight* l = &one;
  Vec3 local[8];
  std::size_t n = std::min<std::size_t>(polygon.size(), 8);
  for (std::size_t k = 0; k < n; ++k) local[k] = l->frame.toLocal(polygon[k]);
  PolygonRegion region(std::span<const Vec3>(local, n));
  const double area = region.area;
  if (!(area > 1e-14)) {
    Vec3 c(0.0);
    for (std::size_t k = 0; k < polygon.size(); ++k) c += polygon[k];
    return glm::length(c) > 0.0 ? intensityOfPart(*l, glm::normalize(c)) : Rgb(0.0);
  }
  Rgb sum(0.0);
  if (const auto* h = std::get_if<HaarDistribution>(&l->dist)) {
    // A planar node's tree is in its own frame, whose lower octants are empty: nothing is sent below
    // its plane, as intensity() says.
    // Most receivers are seen within one leaf cell (a cell of dir-max-level 3 spans about 11
    // degrees): the mean is then that cell's value, found by descent to the region's centre.
    FaceTri cell;
    const std::uint32_t leaf = h->locate(region.cap.centre, &cell);
    Vec3 m[3];
    insideNormals(cell.p[0], cell.p[1], cell.p[2], m);
    if (sideOf(region, m) == Side::Within) {
      const float* v = h->nodes()[leaf].rgb;
      Rgb mean(v[0], v[1], v[2]);
      return hr::allFinite(mean) ? glm::max(mean, Rgb(0.0)) : Rgb(0.0);
    }
    for (int f = 0; f < 8; ++f) sum += haarIntegral(*h, std::uint32_t(f), octaRoot(f), f, 0, std::uint64_t(f), region);
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
        part += intensityOfPart(*l, sampleTriangle(glm::normalize(a), glm::normalize(b), glm::normalize(c), (i + 0.5) / 4, (j + 0.5) / 4));
    sum += part * (w / 16.0);
  }
  Rgb mean = sum / area;
  return hr::allFinite(mean) ? glm::max(mean, Rgb(0.0)) : Rgb(0.0);
}

}  // namespace glossy
