// Cone bounds by hierarchical culling with hull caps and an exact cone-triangle test at the leaves
// (Haar, tetrahedron), and by a covering grid with a Bernstein slack (spherical harmonics). Margins:
// caps and cells meet with 1e-9 to spare in cosine, and the tetrahedron's bound is raised by 1e-12
// relative for barycentric rounding.
#include <glossy/bound.h>
#include <glossy/cell_rules.h>

#include <algorithm>

namespace glossy {

namespace {

/// Cells' hull caps from the upper cells' tables where they hold them (the same values).
void haarVisit(const HaarDistribution& d, std::uint32_t i, const FaceTri& t, int face, int level, std::uint64_t index,
               const Cap& cone, Rgb& best) {
  const auto& n = d.nodes()[i];
  if (!CellGeometry(t, face, level, index).cap.overlaps(cone)) return;
  if (n.child == 0) {
    if (meets(cone, t)) best = glm::max(best, Rgb(n.rgb[0], n.rgb[1], n.rgb[2]));
    return;
  }
  for (std::uint32_t k = 0; k < 4; ++k)
    haarVisit(d, n.child + k, t.child(int(k)), face, level + 1, 4 * index + k, cone, best);
}

void tetraVisit(const TetraDistribution& d, std::uint32_t index, const FaceTri& t, int level, const Cap& cone, Rgb& best) {
  if (!Cap::around(t).overlaps(cone)) return;
  const TetraMesh& m = d.mesh();
  if (level == m.level()) {
    if (!meets(cone, t)) return;
    for (std::uint32_t v : m.triangle(index)) best = glm::max(best, d.vertexValue(v));
    return;
  }
  for (int k = 0; k < 4; ++k) tetraVisit(d, index * 4 + std::uint32_t(k), t.child(k), level + 1, cone, best);
}

}  // namespace

Rgb boundOver(const HaarDistribution& d, const Cap& cone) {
  if (cone.whole()) return d.peak();
  Rgb best(0.0);
  for (int f = 0; f < 8; ++f) haarVisit(d, std::uint32_t(f), octaRoot(f), f, 0, std::uint64_t(f), cone, best);
  return best;
}

Rgb boundOver(const TetraDistribution& d, const Cap& cone) {
  Rgb best(0.0);
  const TetraMesh& m = d.mesh();
  if (cone.whole()) {
    for (std::size_t i = 0; i < m.vertexCount(); ++i) best = glm::max(best, d.vertexValue(i));
  } else {
    for (int f = 0; f < 4; ++f) tetraVisit(d, std::uint32_t(f), m.rootFace(f), 0, cone, best);
  }
  return best * (1.0 + 1e-12);
}

Rgb shMagnitudeBound(const ShDistribution& d) {
  // |sum_m c_lm Y_lm| <= |c_l| |Y_l| and sum_m Y_lm^2 = (2l + 1) / (4 pi) everywhere.
  const int L = d.order();
  Rgb b(0.0);
  for (int l = 0; l < L; ++l) {
    Rgb norm2(0.0);
    for (int m = -l; m <= l; ++m) {
      Rgb c = d.coefficient(std::size_t(l * l + l + m));
      norm2 += c * c;
    }
    b += std::sqrt((2.0 * l + 1.0) / (4.0 * kPi)) * glm::sqrt(norm2);
  }
  return b;
}

Rgb boundOver(const ShDistribution& d, const Cap& cone) {
  const Rgb B = shMagnitudeBound(d) * (1.0 + 1e-6);  // float coefficients evaluated in double
  const int degree = d.order() - 1;
  if (degree == 0 || cone.whole()) return B;
  // Rings every h in polar angle up to the cone's half-angle, each with points at most h apart:
  // every direction of the cone lies within h of a grid point. About 256 points at most: the oracle
  // calls this per link, and a tighter grid costs time in proportion (glossy_extension/README.md).
  const double alpha = std::acos(glm::clamp(cone.cosR, -1.0, 1.0));
  const double capArea = 2.0 * kPi * (1.0 - cone.cosR);
  double h = std::max(std::sqrt(capArea / 256.0) * 1.5, 1e-4);
  Vec3 u, v;
  orthonormalBasis(cone.centre, u, v);
  Rgb best(-1e300);
  int rings = std::max(1, int(std::ceil(alpha / h)));
  for (int i = 0; i <= rings; ++i) {
    double theta = std::min(alpha, i * h);
    double st = std::sin(theta), ct = std::cos(theta);
    // A direction at polar angle theta is within h/2 of the nearest ring along its meridian, and
    // within sin(theta_i) pi / n <= h/2 of the nearest point along that ring.
    int n = std::max(1, int(std::ceil(2.0 * kPi * st / h)));
    for (int j = 0; j < n; ++j) {
      double phi = 2.0 * kPi * j / n;
      best = glm::max(best, d.eval(ct * cone.centre + st * (std::cos(phi) * u + std::sin(phi) * v)));
    }
  }
  Rgb slack = double(degree) * B * h;
  return glm::min(B, best * (1.0 + 1e-6) + slack + 1e-6 * B);
}

}  // namespace glossy
