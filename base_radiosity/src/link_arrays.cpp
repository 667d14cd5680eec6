// Growing and copying link arrays in parallel (link_arrays.h).
#include "link_arrays.h"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace hr::detail {
namespace {

constexpr std::size_t kPage = 4096;

/// Writes one byte in every page of v's storage, in parallel. The kernel maps and zeroes a page on
/// its first write: from one thread, a few hundred thousand such faults per solve cost more than the
/// copying itself. Only bytes no link occupies yet are written (v is empty: its storage is raw).
void touchPages(std::vector<Link>& v) {
  unsigned char* bytes = reinterpret_cast<unsigned char*>(v.data());
  const std::size_t size = v.capacity() * sizeof(Link);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, (size + kPage - 1) / kPage, 64), [&](const auto& r) {
    for (std::size_t p = r.begin(); p != r.end(); ++p) bytes[p * kPage] = 0;
  });
}

}  // namespace

void copyLinks(const Link* src, std::size_t n, Link* dst) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& r) {
    std::copy(src + r.begin(), src + r.end(), dst + r.begin());
  });
}

void reserveLinks(std::vector<Link>& v, std::size_t n) {
  if (n <= v.capacity()) return;
  std::vector<Link> w;
  w.reserve(n);
  touchPages(w);
  w.resize(v.size());
  copyLinks(v.data(), v.size(), w.data());
  v.swap(w);
}

void growLinks(std::vector<Link>& v, std::size_t n) {
  if (n > v.capacity()) reserveLinks(v, std::max(n, v.capacity() + v.capacity() / 2));
  v.resize(n);
}

}  // namespace hr::detail
