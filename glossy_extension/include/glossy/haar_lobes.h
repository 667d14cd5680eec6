// Haar projection of a leaf's reflected lobes, directly at the stored levels: every cell of
// dir-max-level that a lobe reaches gets the integral of that lobe over it by a cell quadrature fine
// enough for the lobe (cell_rules.h), coarser cells the sums of their children, and the stored tree is
// then cut from these exact means by the relative refiner (haarSum, the pull's machinery). No point of
// a fine reference tree is evaluated where no stored value needs it.
//
// Per lobe (mirror m, exponent n, sigma = 1/sqrt(n) its angular width), only cells that meet its reach,
// the cap where cos^n >= 1e-4 (about 4.3 sigma; the part of its power beyond is about 1e-4), are
// visited, and a cell's quadrature is chosen from the cell size h against sigma:
// - the rule's cells are those of dir-max-level when h <= 3.5 sigma there, else of the first finer level
//   where that holds (subdivided only inside the reach): a lobe narrower than a stored cell is
//   resolved below it and summed into it, so it keeps its power;
// - Radon's 7-point rule where h <= 1.6 sigma, Dunavant's 16-point rule up to 3.5 sigma. Single lobes,
//   worst cell mean (cells above 1 % of the peak) against dense quadrature: 5.4e-3 and 2.9e-3 at
//   those limits, relative L1 4e-4; on sample sets like the real ones the worst is 2.9e-3
//   (IsReflection.ProjectionMatchesDenseQuadratureOfTheLobes);
// - a lobe narrower than a cell of level 16 (n beyond about 10^9) puts its whole integral,
//   2 pi / (n + 1) cos(theta_m), in the stored cell holding its axis.
// On the glossy Cornell box's reflections (n = 60 and 300, levels 1-3) that is about 340 and 280
// lobe evaluations per lobe (bench/bench_reflect.cpp).
#pragma once
#include <glossy/haar.h>
#include <glossy/reflection.h>

#include <cstdint>
#include <vector>

namespace glossy {

/// base * scale (when given, at this level) plus the lobes' integrals over the cells of `level`; adds
/// the lobe evaluations to `evaluations`.
HaarCellSums integrateLobesHaar(const LobeSet& lobes, int level, std::uint64_t& evaluations,
                                const HaarCellSums* base = nullptr, double scale = 1.0);

/// The lobes' integral over the one upper cell (level, index) (W), as integrateLobesHaar at `store`
/// would sum it from its cells there (to rounding: summed in another order), but visiting only the
/// cells inside that one (the
/// display reads one cell per view: shown_light.h).
Rgb integrateLobesInCell(const LobeSet& lobes, int store, int level, std::uint64_t index, std::uint64_t& evaluations);

/// The lobes (in a planar leaf's frame: normal +z), and base * scale when given (at o.maxLevel),
/// projected with the options; adds the lobe evaluations (one BRDF evaluation each) to `evaluations`.
HaarDistribution projectLobesHaar(const LobeSet& lobes, const HaarOptions& o, std::uint64_t& evaluations,
                                  const HaarCellSums* base = nullptr, double scale = 1.0);

}  // namespace glossy
