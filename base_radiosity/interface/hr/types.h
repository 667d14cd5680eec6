// Basic value types shared by the whole core: vectors, colours, boxes, and the error type used for
// every user-facing failure (bad scene, bad file). Geometry is double precision so that scenes scaled
// by 1e-3 or 1e3 keep the same relative accuracy; Embree gets floats at its boundary only.
#pragma once
#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace hr {

using Vec3 = glm::dvec3;
using Vec2 = glm::dvec2;
/// Linear RGB triple. Its unit depends on use: W/m^2 for radiosity, W/(m^2 sr) for radiance, W/sr
/// for intensity; every field that holds one says which.
using Rgb = glm::dvec3;

constexpr double kPi = 3.14159265358979323846;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

struct Aabb {
  Vec3 lo{std::numeric_limits<double>::infinity()};
  Vec3 hi{-std::numeric_limits<double>::infinity()};
  void grow(const Vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void grow(const Aabb& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  bool empty() const { return lo.x > hi.x; }
  Vec3 center() const { return 0.5 * (lo + hi); }
  Vec3 extent() const { return hi - lo; }
  double diagonal() const { return empty() ? 0.0 : glm::length(hi - lo); }
};

/// Completes unit vector w to a right-handed orthonormal frame (u, v, w).
inline void orthonormalBasis(const Vec3& w, Vec3& u, Vec3& v) {
  const Vec3 t = std::abs(w.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  u = glm::normalize(glm::cross(t, w));
  v = glm::cross(w, u);
}

inline double maxComponent(const Rgb& c) { return glm::max(c.x, glm::max(c.y, c.z)); }
inline bool allFinite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
/// Photometric weight used wherever one scalar must summarise a colour (Rec. 709 luminance).
inline double luminance(const Rgb& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

/// Every error a user can cause (scene, mesh, solution file, option). The message names the file and
/// the key or line; callers print it and exit non-zero without writing output.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace hr
