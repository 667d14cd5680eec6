// cos^n for one fixed Phong exponent n, evaluated many times (every lobe of a reflection shares its
// material's exponent). std::pow costs about 20 ns; the integer part of n by repeated squaring costs a
// few multiplications (14 at most up to n = 10^4, exact to a few ulps) and only a fractional part needs
// exp2(f log2 c). Cosines where the result would be below 1e-30 give exactly 0: no stored value can show
// that little, and it keeps the squaring chain out of subnormal numbers (which are slow).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace glossy {

class PhongPower {
 public:
  /// Exponents past 2^20 use exp2(n log2 c) whole (the squaring chain would be long).
  static constexpr double kSquaringLimit = 1048576.0;

  explicit PhongPower(double exponent) : n_(std::max(exponent, 0.0)) {
    if (n_ <= kSquaringLimit) {
      integer_ = static_cast<std::uint32_t>(std::floor(n_));
      fraction_ = n_ - double(integer_);
      // An exponent a rounding away from an integer is that integer: MGF's rs 0.1 gives 2 / 0.1^2 - 2 =
      // 197.99999999999997, which sent every cosine of that material through exp2 and log2. Above the
      // cutoff c^n >= 1e-30, so |ln c| <= 69 / n and the power moves by at most 69 * 1e-12 relative.
      if (const double r = std::round(n_); r >= 1.0 && std::abs(n_ - r) <= 1e-12 * n_) {
        integer_ = static_cast<std::uint32_t>(r);
        fraction_ = 0.0;
      }
    } else {
      fraction_ = n_;
    }
    cutoff_ = n_ > 0.0 ? std::pow(1e-30, 1.0 / n_) : 0.0;
  }

  double exponent() const { return n_; }

  /// max(0, c)^n for c <= 1 (c is clamped to 1); 0^0 is 0, as the lobe sends nothing where c <= 0.
  double operator()(double c) const {
    if (!(c > cutoff_)) return 0.0;  // also NaN
    c = std::min(c, 1.0);
    double r = fraction_ != 0.0 ? std::exp2(fraction_ * std::log2(c)) : 1.0;
    double b = c;
    for (std::uint32_t k = integer_; k != 0; k >>= 1) {
      if (k & 1u) r *= b;
      b *= b;
    }
    return r;
  }

  /// For vectorised callers: cos^n = c^integerPart() (by squaring) times c^fraction(), and 0 for
  /// cosines not above cutoff().
  std::uint32_t integerPart() const { return integer_; }
  double fraction() const { return fraction_; }
  double cutoff() const { return cutoff_; }

 private:
  double n_ = 0.0, fraction_ = 0.0, cutoff_ = 0.0;
  std::uint32_t integer_ = 0;
};

}  // namespace glossy
