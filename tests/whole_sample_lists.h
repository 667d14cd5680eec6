// Illumination Samples without reflection in layers, and an extension's statistic by name: what the
// layers tests of both hosts compare against (every leaf gets its whole sample list).
#pragma once
#include <glossy/illumination_samples.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

namespace testutil {

/// Samples with their distance dropped: the host carries them down as they came, not re-aimed from
/// each child, so that layered and whole lists reflect the very same directions.
inline void unaim(std::span<hr::IncidentSample> s) {
  for (hr::IncidentSample& x : s) x.distance = 0.0;
}

/// The layers' bookkeeping tests hold layered against whole lists to 1e-4, what merging a layer's
/// samples rather than a leaf's may move; a wide sender's directions (reflection.h) merge a little
/// differently again (1.65e-4 on the VISION-like host's furnace), so both sides reflect senders as
/// points there.
inline const std::vector<hr::OptionValue> kPointSenders = {{"sender-extent", "off"}};

/// Illumination Samples that never takes a subtree's samples at once: every leaf gets the whole list.
class WholeSampleLists final : public glossy::IlluminationSamples {
 public:
  WholeSampleLists() { configure(kPointSenders); }
  std::size_t reflectShared(hr::NodeId, std::span<hr::IncidentSample> s) override {
    unaim(s);
    return s.size();
  }
};

/// Illumination Samples whose layers take every sample, near senders too (none re-aimed): the layers'
/// bookkeeping held against WholeSampleLists with the same directions on both sides.
class LayersTakingAll final : public glossy::IlluminationSamples {
 public:
  LayersTakingAll() { configure(kPointSenders); }
  std::size_t reflectShared(hr::NodeId e, std::span<hr::IncidentSample> s) override {
    unaim(s);
    return IlluminationSamples::reflectShared(e, s);
  }
};

/// Illumination Samples with no layers that checks every sample a leaf receives: the leaf's centre
/// plus the sample's distance along its direction must land on the centre of a node of the host (its
/// sender's), which holds only if the host re-aimed what it carried down from each ancestor.
class AimChecker final : public glossy::IlluminationSamples {
 public:
  void attach(const hr::HostView& v) override {
    IlluminationSamples::attach(v);
    std::lock_guard lock(mu);
    grid.clear();
    for (std::uint32_t i = 0; i < v.elementCount(); ++i) {
      const hr::NodeInfo n = v.info(hr::NodeId{i});
      add(n.center);
      if (n.leaf && partLevels > 0) addParts(n.bounds);
    }
    for (std::uint32_t i = 0; i < v.clusterCount(); ++i) add(v.info(hr::NodeId{i | hr::NodeId::kClusterBit}).center);
  }
  std::size_t reflectShared(hr::NodeId, std::span<hr::IncidentSample> s) override { return s.size(); }
  void reflect(hr::NodeId leaf, std::span<const hr::IncidentSample> s) override {
    check(leaf, s);
    IlluminationSamples::reflect(leaf, s);
  }
  void reflectShot(hr::NodeId leaf, std::span<const hr::IncidentSample> s) override {
    check(leaf, s);
    IlluminationSamples::reflectShot(leaf, s);
  }
  std::atomic<std::uint64_t> checked{0}, missed{0}, unknown{0};
  /// A host whose leaves send as the parts they would split into (the VISION-like host's senders):
  /// the centres of a leaf's 2^k x 2^k cells, k = 1..partLevels, count as senders' centres too. Only
  /// for faces lying in an axis plane, whose bounds are their rectangle.
  int partLevels = 0;

 private:
  static constexpr double kCell = 1e-3;  // m; a centre matches within 1e-4 m (float directions)
  static std::int64_t cell(double x) { return std::int64_t(std::floor(x / kCell)); }
  static std::uint64_t key(std::int64_t i, std::int64_t j, std::int64_t k) {
    return std::uint64_t(i) * 73856093u ^ std::uint64_t(j) * 19349663u ^ std::uint64_t(k) * 83492791u;
  }
  void addParts(const hr::Aabb& box) {
    const hr::Vec3 e = box.extent();
    int flat = e.x <= e.y && e.x <= e.z ? 0 : (e.y <= e.z ? 1 : 2), u = (flat + 1) % 3, w = (flat + 2) % 3;
    for (int k = 1; k <= partLevels; ++k) {
      const int n = 1 << k;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          hr::Vec3 c = box.center();
          c[u] = box.lo[u] + (i + 0.5) * e[u] / n;
          c[w] = box.lo[w] + (j + 0.5) * e[w] / n;
          add(c);
        }
    }
  }
  void add(const hr::Vec3& c) { grid[key(cell(c.x), cell(c.y), cell(c.z))].push_back(c); }
  bool near(const hr::Vec3& p) const {
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j)
        for (int k = -1; k <= 1; ++k)
          if (auto it = grid.find(key(cell(p.x) + i, cell(p.y) + j, cell(p.z) + k)); it != grid.end())
            for (const hr::Vec3& c : it->second)
              if (glm::length(c - p) < 1e-4) return true;
    return false;
  }
  void check(hr::NodeId leaf, std::span<const hr::IncidentSample> s) {
    if (!view_ || s.empty()) return;  // the host's first push may come before its first attach
    const hr::Vec3 c = view_->info(leaf).center;
    std::lock_guard lock(mu);
    for (const hr::IncidentSample& x : s) {
      if (!(x.distance > 0.0)) {
        ++unknown;
        continue;
      }
      ++checked;
      if (!near(c + x.distance * x.toSender)) ++missed;
    }
  }
  std::mutex mu;
  std::unordered_map<std::uint64_t, std::vector<hr::Vec3>> grid;  // node centres by 1 mm cell
};

/// The extension's statistic of that name, -1 when it has none.
inline double statOf(const hr::Extension& e, const std::string& name) {
  for (const auto& s : e.stats())
    if (s.name == name) return s.value;
  return -1.0;
}

/// The layered run did use layers, and reflected fewer than half the samples the whole lists did.
inline void expectLayersTookMostSamples(const hr::Extension& layered, const hr::Extension& whole) {
  const double layers = statOf(layered, "reflect_shared_layers");
  const double a = statOf(layered, "samples_received_total"), b = statOf(whole, "samples_received_total");
  std::printf("layers %.0f; samples reflected %.0f layered, %.0f whole (%.2f)\n", layers, a, b, a / b);
  EXPECT_GT(layers, 0.0);
  EXPECT_LT(a, 0.5 * b);
}

}  // namespace testutil
