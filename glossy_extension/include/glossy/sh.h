// Real spherical harmonics of configurable order: the directional representation of the original
// Radiance Clustering method (the paper's footnote says it should have been compared; here it is).
// Order L keeps the bands l = 0..L-1, L^2 RGB coefficients. Projection integrates f against each basis
// function by Gauss-Legendre in cos(theta) times uniform phi; evaluation runs the associated Legendre
// recurrence. Truncated sharp lobes ring and go negative: that is the basis, measured, not hidden.
#pragma once
#include <glossy/sphere.h>

#include <iosfwd>
#include <vector>

namespace glossy {

class ShDistribution {
 public:
  static constexpr int kMaxOrder = 32;
  explicit ShDistribution(int order = 4);

  /// Projects f (unit direction -> Rgb). quadrature = number of Gauss-Legendre nodes in cos(theta)
  /// (2x as many in phi); 0 chooses max(2 * order, 128), enough for lobes a few degrees wide.
  template <class F>
  static ShDistribution project(F&& f, int order, int quadrature = 0) {
    ShDistribution d(order);
    Grid g = grid(order, quadrature);
    std::vector<double> y(d.basisCount());
    std::vector<double> acc(3 * d.basisCount(), 0.0);
    for (std::size_t k = 0; k < g.dirs.size(); ++k) {
      Rgb v = f(g.dirs[k]);
      d.basis(g.dirs[k], y.data());
      for (std::size_t i = 0; i < y.size(); ++i)
        for (int c = 0; c < 3; ++c) acc[3 * i + std::size_t(c)] += g.weights[k] * v[c] * y[i];
    }
    for (std::size_t i = 0; i < acc.size(); ++i) d.c_[i] = static_cast<float>(acc[i]);
    return d;
  }

  Rgb eval(const Vec3& d) const;
  void add(const ShDistribution& other);
  void scale(double s);
  /// Power, W: only the l = 0 term integrates to nonzero, 4 pi * c00 * Y00.
  Rgb integral() const;
  std::size_t coefficients() const { return basisCount(); }
  std::size_t bytes() const { return sizeof(*this) + c_.capacity() * sizeof(float); }
  int order() const { return order_; }

  /// Coefficient i (basis function i in (l, m) order), RGB.
  Rgb coefficient(std::size_t i) const { return {c_[3 * i], c_[3 * i + 1], c_[3 * i + 2]}; }

  /// The L^2 basis values at unit direction d, in (l, m) order, m = -l..l.
  void basis(const Vec3& d, double* out) const;

  void serialize(std::ostream& out) const;
  static ShDistribution deserialize(std::istream& in);

 private:
  struct Grid {
    std::vector<Vec3> dirs;
    std::vector<double> weights;
  };
  static Grid grid(int order, int quadrature);
  std::size_t basisCount() const { return std::size_t(order_) * std::size_t(order_); }
  int order_;
  std::vector<float> c_;  // 3 per basis function
};

}  // namespace glossy
