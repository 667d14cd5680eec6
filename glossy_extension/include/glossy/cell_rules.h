// Quadrature over the octahedron's upper cells (z > 0: the four faces a planar leaf's frame puts above
// its surface), for integrating reflected lobes cell by cell. A cell is a planar triangle on an
// octahedron face seen from the centre; a triangle rule placed on the planar triangle, each weight
// times the Jacobian of the central projection (1/|p|^3) and normalised to the cell's exact solid
// angle, integrates constants exactly and smooth functions to the rule's degree. The weights also hold
// the cosine to the normal (z): sum_k weight_k g(dir_k) ~ integral over the cell of g(w) w_z dw.
//
// Two interior rules (no shared points): Radon's 7-point rule of degree 5 and Dunavant's 16-point
// rule of degree 8. Measured on single cos^n lobes (sigma = 1/sqrt(n), cells of nominal size
// h = 90 deg / 2^L, 60 random mirror directions), worst error of a cell mean over cells above 1 % of
// the peak: Radon 9e-4 at h = sigma, 1.7e-3 at 1.2 sigma, 5.4e-3 at 1.6 sigma, 1.2e-2 at 2 sigma;
// Dunavant 1.1e-3 at 2.8 sigma, 2.9e-3 at 3.4 sigma, 9.4e-3 at 3.8 sigma (glossy_extension/README.md).
// Rules with points on the corners (shared by neighbouring cells, about 3 evaluations per cell) have
// degree 3 at most and need h <= 0.4 sigma for the same accuracy: several times more evaluations.
//
// Cells of one level are numbered face * 4^level + (base-4 path), faces 0-3 (the octants with z > 0,
// octaRoot's numbering); the children of cell i are 4i .. 4i+3. Levels up to kTableLevel are tabulated
// once (caps, solid angles and, per rule, the points), lazily and thread-safely; deeper cells are
// computed when visited (only lobes far narrower than the stored cells go there).
#pragma once
#include <glossy/spherical_geometry.h>

#include <cstdint>
#include <vector>

namespace glossy {

enum class CellRule { Radon7 = 0, Dunavant16 = 1 };

inline int rulePoints(CellRule r) { return r == CellRule::Radon7 ? 7 : 16; }

/// Points are kept in blocks of 8 (x[8], y[8], z[8], w[8]: one block fills the vector registers of a
/// lobe evaluation); Radon's rule is padded with a point of zero weight.
constexpr int kBlockPoints = 8, kBlockDoubles = 4 * kBlockPoints;
inline int ruleBlocks(CellRule r) { return r == CellRule::Radon7 ? 1 : 2; }

/// Nominal angular size (radians) of an octahedron cell of a level: 90 degrees / 2^level.
inline double cellSize(int level) { return 0.5 * kPi / double(std::uint64_t(1) << level); }

/// The rule's points of one cell, in blocks: directions and weights (solid angle, Jacobian and z
/// folded in).
struct CellPoints {
  double block[2][kBlockDoubles];
};
void cellPoints(const FaceTri& t, CellRule rule, CellPoints& out);

/// An upper cell's hull cap (centre, cos and sin of its radius) and solid angle: one record per cell,
/// as a culling test reads them together.
struct CellCap {
  double cx, cy, cz, cosR, sinR, omega;
};

class UpperCells {
 public:
  static constexpr int kTableLevel = 6;  // 16384 cells; the points of Dunavant's rule take 8 MB there
  /// The caps of a level <= kTableLevel, by cell index.
  static const std::vector<CellCap>& caps(int level);
  /// The point blocks of every cell of a level <= kTableLevel, cell after cell (ruleBlocks(rule)
  /// blocks each).
  static const std::vector<double>& points(int level, CellRule rule);
  /// The cell of a level with this index (any level).
  static FaceTri cell(int level, std::uint64_t index);
  /// caps(level).data() for every level up to kTableLevel, fetched once: for descents that visit
  /// many cells per call (all levels are built on first use, a few ms).
  static const CellCap* capsOf(int level);
};

/// The hull cap and solid angle of a cell reached by descent from octaRoot(face) (t its planar
/// corners, index its number as above, counting on through the lower faces 4-7): from the tables where
/// they hold it, otherwise computed (Cap::around, solidAngle); the same values either way. A lower
/// face is its upper face mirrored in z (octaRoot), and so is every cell below it, to the bit (negating
/// z is exact and the cap's dot products do not change): a world-frame cluster's tree reads the tables
/// for its lower half too.
struct CellGeometry {
  Cap cap;
  double omega = -1.0;  // < 0: not tabulated, t.solidAngle() when needed
  CellGeometry(const FaceTri& t, int face, int level, std::uint64_t index) {
    if (level <= UpperCells::kTableLevel) {
      const bool lower = face >= 4;
      const CellCap& c = UpperCells::capsOf(level)[lower ? index - (std::uint64_t(4) << (2 * level)) : index];
      cap.centre = Vec3(c.cx, c.cy, lower ? -c.cz : c.cz);
      cap.cosR = c.cosR;
      cap.sinR = c.sinR;
      omega = c.omega;
    } else {
      cap = Cap::around(t);
    }
  }
  double solidAngle(const FaceTri& t) const { return omega >= 0.0 ? omega : t.solidAngle(); }
};

}  // namespace glossy
