// Gauss-Legendre nodes and weights on [-1, 1]: one rule for every place of the extension that
// integrates a smooth function over an interval (the spherical-harmonic projection's cos(theta), a
// shown source's rectangle).
#pragma once
#include <cmath>
#include <cstddef>
#include <vector>

namespace glossy {

/// The n-point rule by Newton's iteration on P_n: exact for polynomials of degree 2n - 1.
inline void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w) {
  constexpr double pi = 3.14159265358979323846;
  x.assign(std::size_t(n), 0.0);
  w.assign(std::size_t(n), 0.0);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(pi * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int j = 2; j <= n; ++j) {
        double p2 = ((2.0 * j - 1.0) * z * p1 - (j - 1.0) * p0) / j;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) p0 = 1.0, p1 = z;
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-15) break;
    }
    x[std::size_t(i)] = z;
    w[std::size_t(i)] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

}  // namespace glossy
