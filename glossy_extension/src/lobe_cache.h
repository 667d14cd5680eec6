// A per-thread memo of one Phong lobe's integrals over the stored Haar cells. A lobe's shape in a leaf's
// frame is fixed by its mirror direction, the exponent and the stored level; only its weight (the
// sample's irradiance times area and albedo) varies. Every leaf of a planar patch receives the same
// samples from the clusters and elements above it (the host's push copies them down), and links keep
// their directions from sweep to sweep, so the same lobe is integrated again and again: on the simple
// Soda Shoppe a leaf reflected ~200 samples per sweep, most of them its ancestors', each at ~440
// quadrature points. The memo keeps, per lobe, the list of (stored cell, integral of the unit-weight
// lobe over it); a hit replays the list.
//
// Determinism: hit or miss, the deposits come from the same list in the same order (a miss computes
// the list, then replays it), so the result does not depend on which thread saw a lobe first or on
// what the memo held. The memo is a pure function cache: it is never invalidated, only emptied when it
// outgrows its bound (maxEntries() shares and an eighth as many lobes per thread; a memory budget
// lowers it, since the budget cannot see a cache's growth coming).
#pragma once
#include <glossy/spherical_geometry.h>

#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

namespace glossy {

/// One stored cell's share of a unit-weight lobe: the integral over the cell of
/// max(0, m.w)^n cos(theta) dw (the cosine to the leaf's normal included), sr.
struct CellShare {
  std::uint32_t cell;
  double integral;
};

class LobeCache {
 public:
  /// Cell shares one thread may hold before the memo is emptied by default: 1 M, 16 MB (and up to
  /// an eighth as many lobes, whose table of slots takes under 32 MB).
  static constexpr std::size_t kMaxEntries = std::size_t(1) << 20;
  /// Resident bytes a memo of `entries` shares may reach: the pool and the table of lobes.
  static constexpr std::size_t kBytesPerEntry = sizeof(CellShare) + 32;
  /// The bound every thread's memo keeps from its next insert on (any thread may set it, between
  /// phases); at least a few lobes' worth, at most kMaxEntries.
  static void setMaxEntries(std::size_t entries);
  static std::size_t maxEntries();

  struct Key {
    double m[3];
    double exponent;
    std::int64_t level;  // 64 bits: no padding, so keys compare as bytes
  };

  /// The shares of a lobe seen before, or false.
  bool find(const Key& k, std::span<const CellShare>& out) const;
  /// Remembers a lobe's shares (after a miss); returns the stored copy.
  std::span<const CellShare> insert(const Key& k, std::span<const CellShare> shares);

  std::uint64_t hits = 0, misses = 0;
  /// What the memo holds now: cell shares, and lobes.
  std::size_t heldShares() const { return pool_.size(); }
  std::size_t heldLobes() const { return used_; }

 private:
  struct Slot {
    Key key;
    std::uint32_t offset = 0, count = 0;
    bool used = false;
  };
  static std::uint64_t hash(const Key& k);
  static bool same(const Key& a, const Key& b) { return std::memcmp(&a, &b, sizeof(Key)) == 0; }
  std::size_t probe(const Key& k) const;
  void clear();

  std::vector<Slot> slots_;       // open addressing, linear probing, power-of-two size, at most half full
  std::vector<CellShare> pool_;   // every lobe's shares, one run per lobe
  std::size_t used_ = 0;
};

/// The calling thread's memo.
LobeCache& lobeCache();

}  // namespace glossy
