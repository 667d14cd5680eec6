// Real spherical harmonics: normalisation table, the associated Legendre recurrence, the projection
// grid (Gauss-Legendre in cos(theta), uniform in phi: exact for band-limited integrands of the order
// used), arithmetic and serialization.
#include <glossy/gauss_legendre.h>
#include <glossy/serial.h>
#include <glossy/sh.h>

#include <array>
#include <istream>
#include <ostream>
#include <stdexcept>

namespace glossy {

namespace {

constexpr int kN = ShDistribution::kMaxOrder;

/// K(l, m) = sqrt((2l + 1) / (4 pi) * (l - m)! / (l + m)!), built once.
const std::array<double, kN * kN>& normalisation() {
  static const auto table = [] {
    std::array<double, kN * kN> k{};
    for (int l = 0; l < kN; ++l)
      for (int m = 0; m <= l; ++m) {
        double ratio = 1.0;
        for (int i = l - m + 1; i <= l + m; ++i) ratio /= i;
        k[std::size_t(l * kN + m)] = std::sqrt((2.0 * l + 1.0) / (4.0 * kPi) * ratio);
      }
    return k;
  }();
  return table;
}

}  // namespace

ShDistribution::ShDistribution(int order) : order_(order) {
  if (order < 1 || order > kMaxOrder)
    throw std::invalid_argument("spherical harmonics order " + std::to_string(order) + " outside 1.." +
                                std::to_string(kMaxOrder));
  c_.assign(3 * basisCount(), 0.0f);
}

void ShDistribution::basis(const Vec3& d, double* out) const {
  const auto& K = normalisation();
  double z = glm::clamp(d.z, -1.0, 1.0);
  double rxy = std::sqrt(d.x * d.x + d.y * d.y);
  double cphi = rxy > 0.0 ? d.x / rxy : 1.0, sphi = rxy > 0.0 ? d.y / rxy : 0.0;
  double sint = std::sqrt(std::max(0.0, 1.0 - z * z));
  const int L = order_;
  double pmm = 1.0;              // P_m^m(z)
  double cm = 1.0, sm = 0.0;     // cos(m phi), sin(m phi)
  for (int m = 0; m < L; ++m) {
    if (m > 0) {
      pmm *= -(2.0 * m - 1.0) * sint;
      double c = cm * cphi - sm * sphi;
      sm = sm * cphi + cm * sphi;
      cm = c;
    }
    double pPrev = 0.0, p = pmm;  // P_{l-1}^m, P_l^m for l = m
    for (int l = m; l < L; ++l) {
      if (l == m + 1) {
        pPrev = p;
        p = z * (2.0 * m + 1.0) * pmm;
      } else if (l > m + 1) {
        double next = ((2.0 * l - 1.0) * z * p - (l + m - 1.0) * pPrev) / (l - m);
        pPrev = p;
        p = next;
      }
      double k = K[std::size_t(l * kN + m)];
      std::size_t base = std::size_t(l * l + l);
      if (m == 0) {
        out[base] = k * p;
      } else {
        out[base + std::size_t(m)] = std::sqrt(2.0) * k * cm * p;
        out[base - std::size_t(m)] = std::sqrt(2.0) * k * sm * p;
      }
    }
  }
}

Rgb ShDistribution::eval(const Vec3& d) const {
  double y[kN * kN];
  basis(glm::normalize(d), y);
  Rgb sum(0.0);
  for (std::size_t i = 0; i < basisCount(); ++i) sum += y[i] * Rgb(c_[3 * i], c_[3 * i + 1], c_[3 * i + 2]);
  return sum;
}

ShDistribution::Grid ShDistribution::grid(int order, int quadrature) {
  int n = quadrature > 0 ? quadrature : std::max(2 * order, 128);
  std::vector<double> x, w;
  gaussLegendre(n, x, w);
  int m = 2 * n;
  Grid g;
  g.dirs.reserve(std::size_t(n * m));
  g.weights.reserve(std::size_t(n * m));
  for (int i = 0; i < n; ++i) {
    double s = std::sqrt(std::max(0.0, 1.0 - x[std::size_t(i)] * x[std::size_t(i)]));
    for (int j = 0; j < m; ++j) {
      double phi = 2.0 * kPi * (j + 0.5) / m;
      g.dirs.emplace_back(s * std::cos(phi), s * std::sin(phi), x[std::size_t(i)]);
      g.weights.push_back(w[std::size_t(i)] * 2.0 * kPi / m);
    }
  }
  return g;
}

void ShDistribution::add(const ShDistribution& other) {
  if (other.order_ != order_) throw std::invalid_argument("adding spherical harmonics of different orders");
  for (std::size_t i = 0; i < c_.size(); ++i) c_[i] += other.c_[i];
}

void ShDistribution::scale(double s) {
  for (float& v : c_) v = static_cast<float>(v * s);
}

Rgb ShDistribution::integral() const {
  // Y00 = 1 / sqrt(4 pi); every other basis function integrates to zero.
  return std::sqrt(4.0 * kPi) * Rgb(c_[0], c_[1], c_[2]);
}

void ShDistribution::serialize(std::ostream& out) const {
  serial::writeHeader(out, serial::kShTag);
  serial::writeU32(out, static_cast<std::uint32_t>(order_));
  for (float v : c_) serial::writeF32(out, v);
}

ShDistribution ShDistribution::deserialize(std::istream& in) {
  serial::readHeader(in, serial::kShTag, "spherical harmonics distribution");
  std::uint32_t order = serial::readU32(in);
  if (order < 1 || order > std::uint32_t(kMaxOrder))
    throw std::runtime_error("spherical harmonics distribution: bad order " + std::to_string(order));
  ShDistribution d(static_cast<int>(order));
  for (float& v : d.c_) {
    v = serial::readF32(in);
    if (!std::isfinite(v)) throw std::runtime_error("spherical harmonics distribution: non-finite value");
  }
  return d;
}

}  // namespace glossy
