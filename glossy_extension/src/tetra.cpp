// Building the subdivided tetrahedron once per level: shared vertices (midpoints are bitwise equal
// from both sides of an edge, so exact keys deduplicate them), leaf triangles in descent order, and
// the integration weight of every vertex's hat function over the sphere.
#include <glossy/serial.h>
#include <glossy/tetra.h>

#include <istream>
#include <map>
#include <memory>
#include <mutex>
#include <ostream>
#include <stdexcept>

namespace glossy {

namespace {

/// A sub-triangle of a leaf cell with the barycentric coordinates (in the leaf) of its corners.
struct BaryTri {
  FaceTri t;
  Vec3 bc[3];
};

BaryTri childOf(const BaryTri& p, int k) {
  Vec3 m01 = 0.5 * (p.bc[0] + p.bc[1]), m12 = 0.5 * (p.bc[1] + p.bc[2]), m20 = 0.5 * (p.bc[2] + p.bc[0]);
  BaryTri c{p.t.child(k), {}};
  switch (k) {
    case 0: c.bc[0] = p.bc[0], c.bc[1] = m01, c.bc[2] = m20; break;
    case 1: c.bc[0] = m01, c.bc[1] = p.bc[1], c.bc[2] = m12; break;
    case 2: c.bc[0] = m20, c.bc[1] = m12, c.bc[2] = p.bc[2]; break;
    default: c.bc[0] = m12, c.bc[1] = m20, c.bc[2] = m01; break;
  }
  return c;
}

/// Adds the integral of the three hat functions over the spherical cell, by 4^depth sub-triangles
/// (solid angle times the barycentric coordinates at the sub-triangle's centroid).
void integrateHats(const BaryTri& b, int depth, Vec3& acc) {
  if (depth == 0) {
    acc += b.t.solidAngle() * (b.bc[0] + b.bc[1] + b.bc[2]) / 3.0;
    return;
  }
  for (int k = 0; k < 4; ++k) integrateHats(childOf(b, k), depth - 1, acc);
}

}  // namespace

TetraMesh::TetraMesh(int level) : level_(level) {
  const double s = 1.0 / std::sqrt(3.0);
  corner_[0] = Vec3(1, 1, 1) * s;
  corner_[1] = Vec3(1, -1, -1) * s;
  corner_[2] = Vec3(-1, 1, -1) * s;
  corner_[3] = Vec3(-1, -1, 1) * s;
  for (int f = 0; f < 4; ++f) {
    FaceTri r = root(f);
    toBary_[f] = glm::inverse(glm::dmat3(r.p[0], r.p[1], r.p[2]));
  }
  std::map<std::array<double, 3>, std::uint32_t> index;
  auto vertexOf = [&](const Vec3& p) {
    auto [it, fresh] = index.try_emplace({p.x, p.y, p.z}, static_cast<std::uint32_t>(dirs_.size()));
    if (fresh) dirs_.push_back(glm::normalize(p));
    return it->second;
  };
  // Leaves in descent order: triangle index = face * 4^n + the base-4 digits of its path.
  auto build = [&](auto&& self, const FaceTri& t, int l) -> void {
    if (l == level_) {
      tris_.push_back({vertexOf(t.p[0]), vertexOf(t.p[1]), vertexOf(t.p[2])});
      cells_.push_back(t);
      return;
    }
    for (int k = 0; k < 4; ++k) self(self, t.child(k), l + 1);
  };
  for (int f = 0; f < 4; ++f) build(build, root(f), 0);
  weights_.assign(dirs_.size(), 0.0);
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    Vec3 acc(0.0);
    // Coarse cells are curved and need the finer sub-tiling; fine cells are nearly flat.
    integrateHats(BaryTri{cells_[t], {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}}, level_ >= 5 ? 1 : 4, acc);
    // The sub-triangles tile the cell exactly, so the three weights sum to its solid angle.
    for (int k = 0; k < 3; ++k) weights_[tris_[t][std::size_t(k)]] += acc[k];
  }
}

FaceTri TetraMesh::root(int f) const {
  // The face opposite corner f, with the other three corners in increasing order.
  FaceTri t;
  int j = 0;
  for (int k = 0; k < 4; ++k)
    if (k != f) t.p[j++] = corner_[k];
  return t;
}

double TetraMesh::cellSolidAngle(std::size_t t) const { return cells_[t].solidAngle(); }

const TetraMesh& TetraMesh::get(int level) {
  if (level < 0 || level > kMaxLevel)
    throw std::invalid_argument("tetrahedron level " + std::to_string(level) + " outside 0.." + std::to_string(kMaxLevel));
  static std::once_flag once[kMaxLevel + 1];
  static std::unique_ptr<TetraMesh> meshes[kMaxLevel + 1];
  std::call_once(once[level], [level] { meshes[level].reset(new TetraMesh(level)); });
  return *meshes[level];
}

TetraDistribution::TetraDistribution(int level) : mesh_(&TetraMesh::get(level)), rgb_(3 * mesh_->vertexCount(), 0.0f) {}

void TetraDistribution::add(const TetraDistribution& other) {
  if (other.mesh_ != mesh_) throw std::invalid_argument("adding tetrahedron distributions of different levels");
  for (std::size_t i = 0; i < rgb_.size(); ++i) rgb_[i] += other.rgb_[i];
}

void TetraDistribution::scale(double s) {
  for (float& v : rgb_) v = static_cast<float>(v * s);
}

Rgb TetraDistribution::integral() const {
  Rgb sum(0.0);
  for (std::size_t i = 0; i < mesh_->vertexCount(); ++i)
    sum += mesh_->weight(i) * Rgb(rgb_[3 * i], rgb_[3 * i + 1], rgb_[3 * i + 2]);
  return sum;
}

void TetraDistribution::serialize(std::ostream& out) const {
  serial::writeHeader(out, serial::kTetraTag);
  serial::writeU32(out, static_cast<std::uint32_t>(level()));
  for (float v : rgb_) serial::writeF32(out, v);
}

TetraDistribution TetraDistribution::deserialize(std::istream& in) {
  serial::readHeader(in, serial::kTetraTag, "tetrahedron distribution");
  std::uint32_t level = serial::readU32(in);
  if (level > std::uint32_t(TetraMesh::kMaxLevel))
    throw std::runtime_error("tetrahedron distribution: bad level " + std::to_string(level));
  TetraDistribution d(static_cast<int>(level));
  for (float& v : d.rgb_) {
    v = serial::readF32(in);
    if (!std::isfinite(v)) throw std::runtime_error("tetrahedron distribution: non-finite value");
  }
  return d;
}

}  // namespace glossy
