// A flat sender's shape as a display needs it: the rectangle of the same second moments in the
// sender's plane. A glossy highlight is its source's shape convolved with the lobe; a source drawn as
// a disk of its spread showed floor_gloss's tilted rectangular lamp up to 7 % off in the pixels about
// its highlight. Hosts describe each flat sender this way (IncidentSample::senderShape), and the
// extension joins the pieces of one sender by adding their moments, which for a lamp's quarters gives
// the lamp back. Here, once, so that hosts and extension compute it alike.
#pragma once
#include <hr/types.h>

#include <algorithm>
#include <cmath>

namespace hr {

/// Half the longer axis of the rectangle (m, in the plane; zero: no shape known) and half its width
/// along normal x axis (m).
struct SenderRectangle {
  glm::vec3 axis{0.0f};
  float halfWidth = 0.0f;
};

/// The rectangle of area covariance c (m^2, about the centroid) in the plane of unit normal n: its
/// axes along the in-plane eigenvectors of c, each half-length sqrt(3 lambda) (a uniform rectangle of
/// half-length a has variance a^2 / 3 along it). Out-of-plane parts of c are left out. Where the
/// variances nearly agree (a square, or a square lamp's quarters joined) moments name no axis to
/// speak of and rounding or the pieces' brightness would turn the square: so when c is diagonal, to
/// 1e-3 of its trace, in the frame of `hint` (an edge, or a piece's axis; zero: none) and n x hint,
/// the axes are that frame's.
inline SenderRectangle rectangleOfMoments(const glm::dmat3& c, const Vec3& n, const Vec3& hint = Vec3(0.0)) {
  SenderRectangle r;
  auto in = [&](const Vec3& a, const Vec3& b) { return glm::dot(a, c * b); };
  if (const Vec3 h = hint - glm::dot(hint, n) * n; glm::dot(h, h) > 0.0) {
    const Vec3 a = glm::normalize(h), b = glm::cross(n, a);
    const double xx = in(a, a), yy = in(b, b), xy = in(a, b);
    if (std::isfinite(xx + yy + xy) && xx + yy > 0.0 && std::abs(xy) <= 1e-3 * (xx + yy)) {
      const bool first = xx >= yy;
      r.axis = glm::vec3((first ? a : b) * std::sqrt(3.0 * std::max(xx, yy)));
      r.halfWidth = float(std::sqrt(3.0 * std::max(0.0, std::min(xx, yy))));
      return r;
    }
  }
  Vec3 e1, e2;
  orthonormalBasis(n, e1, e2);
  const double xx = in(e1, e1), yy = in(e2, e2), xy = in(e1, e2);
  const double mean = 0.5 * (xx + yy), half = std::sqrt(0.25 * (xx - yy) * (xx - yy) + xy * xy);
  const double l1 = mean + half, l2 = std::max(0.0, mean - half);
  if (!(l1 > 0.0) || !std::isfinite(l1)) return r;
  // The major eigenvector of [[xx, xy], [xy, yy]]: (xy, l1 - xx) or (l1 - yy, xy), the longer of them.
  Vec2 v(xy, l1 - xx);
  if (const Vec2 w(l1 - yy, xy); glm::dot(w, w) > glm::dot(v, v)) v = w;
  const double len = glm::length(v);
  const Vec3 u = len > 0.0 ? (v.x * e1 + v.y * e2) / len : e1;
  r.axis = glm::vec3(u * std::sqrt(3.0 * l1));
  r.halfWidth = float(std::sqrt(3.0 * l2));
  return r;
}

/// The second unit axis of a rectangle in the plane of unit normal n: n x axis, normalised.
inline Vec3 rectangleSide(const glm::vec3& axis, const Vec3& n) {
  const Vec3 w = glm::cross(n, Vec3(axis));
  const double len = glm::length(w);
  return len > 0.0 ? w / len : Vec3(0.0);
}

/// The area covariance (m^2) of the rectangle r in the plane of n, for adding pieces' moments.
inline glm::dmat3 momentsOfRectangle(const SenderRectangle& r, const Vec3& n) {
  const Vec3 a(r.axis), b = rectangleSide(r.axis, n) * double(r.halfWidth);
  return (glm::outerProduct(a, a) + glm::outerProduct(b, b)) / 3.0;
}

}  // namespace hr
