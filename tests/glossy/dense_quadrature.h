// The brute-force reference for reflection: the exact mean of a leaf's lobe sum over any octahedron
// cell, by dense quadrature. Independent of the extension's cell rules: the cell is subdivided until
// its sub-cells are at most 1/6 of the lobes' angular width (sigma = 1/sqrt(n)) and at least two levels
// below it, and each sub-cell takes the degree-2 rule (centre 3/4, corners 1/12) on its planar triangle,
// each weight times the Jacobian of the central projection (1/|p|^3), normalised to the sub-cell's exact
// solid angle (within 1e-4 of a cell mean at that density). Each sub-cell sums only the lobes that reach it
// (above 1e-13 of their peak: far below float), so even n = 10^4 stays affordable.
#pragma once
#include <glossy/reflection.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace testquad {

using glossy::Rgb;
using glossy::Vec3;

/// The lobe sum itself, in the lobes' frame.
inline Rgb exactLobes(const glossy::LobeSet& lobes, const Vec3& w) {
  double c = glm::dot(lobes.normal, w);
  if (c <= 0.0) return Rgb(0.0);
  Rgb sum(0.0);
  for (const glossy::LobeSample& s : lobes.samples) {
    double a = glm::dot(s.mirror, w);
    if (a > 0.0) sum += s.weight * std::pow(std::min(a, 1.0), lobes.exponent);
  }
  return c * sum;
}

class DenseQuadrature {
 public:
  explicit DenseQuadrature(const glossy::LobeSet& lobes) : lobes_(lobes) {
    const double sigma = 1.0 / std::sqrt(std::max(lobes.exponent, 1.0));
    while (0.5 * glossy::kPi / double(1 << finest_) > sigma / 6.0 && finest_ < 14) ++finest_;
    const double cosReach = lobes.exponent > 0.0 ? std::pow(1e-13, 1.0 / lobes.exponent) : -1.0;
    for (const glossy::LobeSample& s : lobes.samples) reach_.push_back(glossy::Cap::cone(s.mirror, cosReach));
  }
  /// The mean over cell t of level `level`, W/sr.
  Rgb mean(const glossy::FaceTri& t, int level) const {
    std::vector<std::size_t> all(lobes_.samples.size());
    for (std::size_t j = 0; j < all.size(); ++j) all[j] = j;
    return integral(t, level, std::max(finest_, level + 2), all) / t.solidAngle();
  }

 private:
  Rgb value(const Vec3& w, const std::vector<std::size_t>& active) const {
    double c = glm::dot(lobes_.normal, w);
    if (c <= 0.0) return Rgb(0.0);
    Rgb sum(0.0);
    for (std::size_t j : active) {
      double a = glm::dot(lobes_.samples[j].mirror, w);
      if (a > 0.0) sum += lobes_.samples[j].weight * std::pow(std::min(a, 1.0), lobes_.exponent);
    }
    return c * sum;
  }
  Rgb integral(const glossy::FaceTri& t, int level, int finest, const std::vector<std::size_t>& parent) const {
    const glossy::Cap hull = glossy::Cap::around(t);
    std::vector<std::size_t> active;
    for (std::size_t j : parent)
      if (reach_[j].overlaps(hull)) active.push_back(j);
    if (active.empty()) return Rgb(0.0);
    if (level >= finest) {
      const Vec3 p[4] = {t.p[0], t.p[1], t.p[2], (t.p[0] + t.p[1] + t.p[2]) / 3.0};
      Rgb sum(0.0);
      double weights = 0.0;
      for (int k = 0; k < 4; ++k) {
        double len = glm::length(p[k]), w = (k == 3 ? 0.75 : 1.0 / 12.0) / (len * len * len);
        sum += w * value(p[k] / len, active);
        weights += w;
      }
      return t.solidAngle() * sum / weights;
    }
    Rgb sum(0.0);
    for (int k = 0; k < 4; ++k) sum += integral(t.child(k), level + 1, finest, active);
    return sum;
  }
  const glossy::LobeSet& lobes_;
  int finest_ = 0;
  std::vector<glossy::Cap> reach_;
};

}  // namespace testquad
