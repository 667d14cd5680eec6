// The non-adaptive basis of the paper (§4.1): a tetrahedron whose faces are subdivided n times,
// 4^(n+1) spherical triangles over 2*4^n + 2 vertices, RGB intensity (W/sr) stored at the vertices and
// interpolated linearly inside each triangle. The mesh of a level is built once and shared by every
// distribution of that level; a distribution holds only its vertex values.
#pragma once
#include <glossy/sphere.h>

#include <array>
#include <cstdint>
#include <iosfwd>
#include <vector>

namespace glossy {

class TetraMesh {
 public:
  static constexpr int kMaxLevel = 8;
  /// The shared mesh of a level (0 to kMaxLevel); built on first use, thread-safe.
  static const TetraMesh& get(int level);

  int level() const { return level_; }
  std::size_t vertexCount() const { return dirs_.size(); }
  std::size_t triangleCount() const { return tris_.size(); }
  const Vec3& vertex(std::size_t i) const { return dirs_[i]; }
  const std::array<std::uint32_t, 3>& triangle(std::size_t t) const { return tris_[t]; }
  /// Solid angle of triangle t, sr (exact).
  double cellSolidAngle(std::size_t t) const;
  /// Integral over the sphere of vertex i's hat function, sr; the weights sum to 4 pi.
  double weight(std::size_t i) const { return weights_[i]; }

  /// Root face f (0-3) as planar corners; its 1->4 descendants at this mesh's level are triangles
  /// f * 4^level + (base-4 path), the order locate() returns.
  FaceTri rootFace(int f) const { return root(f); }

  /// The triangle holding direction d and d's barycentric coordinates in it.
  std::uint32_t locate(const Vec3& d, Bary& b) const {
    int f = 0;
    double best = glm::dot(d, corner_[0]);
    for (int k = 1; k < 4; ++k) {
      double c = glm::dot(d, corner_[k]);
      if (c < best) best = c, f = k;  // the face opposite the corner farthest from d
    }
    Vec3 q = toBary_[f] * d;
    double s = q.x + q.y + q.z;
    b = {q.x / s, q.y / s, q.z / s};
    std::uint32_t t = static_cast<std::uint32_t>(f);
    for (int l = 0; l < level_; ++l) t = t * 4 + static_cast<std::uint32_t>(descend(b));
    return t;
  }

 private:
  explicit TetraMesh(int level);
  FaceTri root(int f) const;
  int level_;
  Vec3 corner_[4];
  glm::dmat3 toBary_[4];
  std::vector<Vec3> dirs_;
  std::vector<std::array<std::uint32_t, 3>> tris_;
  std::vector<FaceTri> cells_;
  std::vector<double> weights_;
};

class TetraDistribution {
 public:
  explicit TetraDistribution(int level = 3);

  /// Samples f (unit direction -> Rgb) at the vertices.
  template <class F>
  static TetraDistribution project(F&& f, int level) {
    TetraDistribution d(level);
    for (std::size_t i = 0; i < d.mesh_->vertexCount(); ++i) d.set(i, f(d.mesh_->vertex(i)));
    return d;
  }

  Rgb eval(const Vec3& d) const {
    Bary b;
    const auto& t = mesh_->triangle(mesh_->locate(d, b));
    const float *v0 = &rgb_[3 * t[0]], *v1 = &rgb_[3 * t[1]], *v2 = &rgb_[3 * t[2]];
    return {b.b0 * v0[0] + b.b1 * v1[0] + b.b2 * v2[0], b.b0 * v0[1] + b.b1 * v1[1] + b.b2 * v2[1],
            b.b0 * v0[2] + b.b1 * v1[2] + b.b2 * v2[2]};
  }

  Rgb vertexValue(std::size_t i) const { return {rgb_[3 * i], rgb_[3 * i + 1], rgb_[3 * i + 2]}; }

  /// Both must have the same level (throws std::invalid_argument otherwise).
  void add(const TetraDistribution& other);
  void scale(double s);
  Rgb integral() const;
  std::size_t coefficients() const { return mesh_->vertexCount(); }
  std::size_t bytes() const { return sizeof(*this) + rgb_.capacity() * sizeof(float); }
  int level() const { return mesh_->level(); }
  const TetraMesh& mesh() const { return *mesh_; }

  void serialize(std::ostream& out) const;
  static TetraDistribution deserialize(std::istream& in);

 private:
  void set(std::size_t i, const Rgb& v) {
    for (int c = 0; c < 3; ++c) rgb_[3 * i + std::size_t(c)] = static_cast<float>(v[c]);
  }
  const TetraMesh* mesh_;
  std::vector<float> rgb_;
};

}  // namespace glossy
