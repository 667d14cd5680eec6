// The per-thread lobe memo (lobe_cache.h): an open-addressing table over one pool of cell shares.
#include "lobe_cache.h"

#include <algorithm>
#include <atomic>

namespace glossy {

namespace {
constexpr std::size_t kInitialSlots = 1 << 12;
constexpr std::size_t kMinEntries = std::size_t(1) << 14;
std::atomic<std::size_t> gMaxEntries{LobeCache::kMaxEntries};
}  // namespace

void LobeCache::setMaxEntries(std::size_t entries) {
  gMaxEntries.store(std::clamp(entries, kMinEntries, kMaxEntries), std::memory_order_relaxed);
}

std::size_t LobeCache::maxEntries() { return gMaxEntries.load(std::memory_order_relaxed); }

std::uint64_t LobeCache::hash(const Key& k) {
  // FNV-1a over the key's bytes, then a final mix: the mirror directions of one patch's lobes differ
  // in their low bits.
  const auto* b = reinterpret_cast<const unsigned char*>(&k);
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < sizeof(Key); ++i) h = (h ^ b[i]) * 1099511628211ull;
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  return h;
}

std::size_t LobeCache::probe(const Key& k) const {
  const std::size_t mask = slots_.size() - 1;
  std::size_t i = std::size_t(hash(k)) & mask;
  while (slots_[i].used && !same(slots_[i].key, k)) i = (i + 1) & mask;
  return i;
}

bool LobeCache::find(const Key& k, std::span<const CellShare>& out) const {
  if (slots_.empty()) return false;
  const Slot& s = slots_[probe(k)];
  if (!s.used) return false;
  out = std::span<const CellShare>(pool_.data() + s.offset, s.count);
  return true;
}

void LobeCache::clear() {
  // The pool is reserved at its bound once: growing it by doubling held the old and the new array at
  // once (24 MB for a moment at the bound), a jump a memory budget (--memory-mb) cannot see coming;
  // reserved pages cost resident memory only once written.
  const std::size_t bound = maxEntries();
  if (pool_.capacity() < bound) pool_.reserve(bound);
  slots_.assign(kInitialSlots, Slot{});
  pool_.clear();
  used_ = 0;
}

std::span<const CellShare> LobeCache::insert(const Key& k, std::span<const CellShare> shares) {
  const std::size_t bound = maxEntries();
  if (slots_.empty() || pool_.size() + shares.size() > bound || 8 * (used_ + 1) > bound) clear();
  if (2 * (used_ + 1) > slots_.size()) {
    // Rehash into twice the slots (the pool stays where it is).
    std::vector<Slot> old(2 * slots_.size());
    old.swap(slots_);
    for (const Slot& s : old)
      if (s.used) slots_[probe(s.key)] = s;
  }
  Slot& s = slots_[probe(k)];
  s.key = k;
  s.offset = std::uint32_t(pool_.size());
  s.count = std::uint32_t(shares.size());
  s.used = true;
  ++used_;
  pool_.insert(pool_.end(), shares.begin(), shares.end());
  return std::span<const CellShare>(pool_.data() + s.offset, s.count);
}

LobeCache& lobeCache() {
  thread_local LobeCache c;
  return c;
}

}  // namespace glossy
