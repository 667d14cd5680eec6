// The VISION-like host's display cells for an unchanged extension (see display_cells.h). The
// solution's elements are cells, not host nodes: cell i shows host leaf cellLeaf[i], and every cell
// of a leaf shares that leaf's light. The extension is asked for the leaf's radiance as seen at the
// cell's (or a pixel's) own normal, so a curved leaf's cells show its glossy light turned with the
// surface (hr/extension.h, radiance with a normal) without a copy or a re-projection per cell.
// The saved section is a header (magic, H, each cell's leaf, the shown leaves' area, normal and
// material) and the extension's own bytes for those leaves; loading rebuilds a view of just those
// leaves, so `render` and the viewer need nothing of the host.
#include "display_cells.h"

#include <hr/solution_view.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace adapters::vision {
namespace {

constexpr std::uint32_t kMagic = 0x32534956u;  // "VIS2": cells share their leaf's light
constexpr std::uint32_t kOldMagic = 0x43534956u;  // "VISC": a copy per cell (before 2026-12-03)
constexpr const char* kWhat = "solution file, section of the extension on the VISION-like host";

[[noreturn]] void refuse(const std::string& why) { throw hr::InputError(std::string(kWhat) + ": " + why); }

void put32(std::ostream& out, std::uint32_t v) {
  char b[4];
  for (int k = 0; k < 4; ++k) b[k] = char((v >> (8 * k)) & 0xFF);
  out.write(b, 4);
}
void put64(std::ostream& out, double x) {
  std::uint64_t v;
  std::memcpy(&v, &x, 8);
  char b[8];
  for (int k = 0; k < 8; ++k) b[k] = char((v >> (8 * k)) & 0xFF);
  out.write(b, 8);
}

/// Little-endian reads that refuse past the end of the section.
struct Reader {
  std::string_view b;
  std::size_t at = 0;
  std::uint64_t raw(int n) {
    if (b.size() - at < std::size_t(n)) refuse("truncated");
    std::uint64_t v = 0;
    for (int k = 0; k < n; ++k) v |= std::uint64_t(static_cast<unsigned char>(b[at + std::size_t(k)])) << (8 * k);
    at += std::size_t(n);
    return v;
  }
  std::uint32_t u32() { return std::uint32_t(raw(4)); }
  double f64() {
    std::uint64_t v = raw(8);
    double x;
    std::memcpy(&x, &v, 8);
    return x;
  }
};

/// What a loaded solution knows of the host: the leaves its cells show (0..H-1, most of them
/// absent), each as the one-normal leaf the extension reflected it as; materials are the solution's.
class LeafView final : public hr::HostView {
 public:
  LeafView(const hr::HostView& cells, std::uint32_t H, std::vector<std::pair<std::uint32_t, hr::NodeInfo>> leaves)
      : cells_(cells), H_(H), leaves_(std::move(leaves)) {}
  hr::NodeId root() const override { return hr::NodeId{0}; }
  hr::NodeInfo info(hr::NodeId n) const override {
    if (n.isCluster()) return {};
    auto it = std::lower_bound(leaves_.begin(), leaves_.end(), n.index(), [](const auto& l, std::uint32_t i) { return l.first < i; });
    return it != leaves_.end() && it->first == n.index() ? it->second : hr::NodeInfo{};
  }
  std::span<const hr::NodeId> children(hr::NodeId) const override { return {}; }
  std::size_t elementCount() const override { return H_; }
  std::size_t clusterCount() const override { return 0; }
  hr::MaterialInfo material(std::uint32_t id) const override { return cells_.material(id); }
  std::size_t materialCount() const override { return cells_.materialCount(); }

 private:
  const hr::HostView& cells_;  // the loaded solution's view, which outlives the extension
  const std::uint32_t H_;
  std::vector<std::pair<std::uint32_t, hr::NodeInfo>> leaves_;  // by id
};

class Adapter final : public hr::Extension {
 public:
  explicit Adapter(std::unique_ptr<hr::Extension> inner) : in_(std::move(inner)) {}

  void show(const hr::HostView& host, const hr::Solution& sol, const std::vector<std::uint32_t>& cellLeaf) {
    H_ = static_cast<std::uint32_t>(host.elementCount());
    if (cellLeaf.size() != sol.elements.size()) throw std::logic_error("display cells: one leaf per solution element expected");
    cellLeaf_ = cellLeaf;
    const hr::SolutionView cells(sol);
    cellNormal_.resize(cellLeaf.size());
    for (std::uint32_t i = 0; i < cellLeaf.size(); ++i) {
      if (cellLeaf[i] >= H_) throw std::logic_error("display cells: a cell names no leaf of the host");
      cellNormal_[i] = cells.info(hr::NodeId{i}).normal;
    }
    cellShare_ = areaShares(cells, cellLeaf_, H_);
    // The leaves the extension may hold light for (the ones it saves): the file says how it saw them.
    shown_.clear();
    for (std::uint32_t l = 0; l < H_; ++l) {
      hr::NodeInfo i = host.info(hr::NodeId{l});
      if (i.leaf && i.material < host.materialCount() && in_->simulates(host.material(i.material))) shown_.push_back({l, i});
    }
    showing_ = true;
  }

  // Solving: the host's own node ids, passed through.
  std::string_view name() const override { return in_->name(); }
  std::vector<hr::OptionSpec> options() const override { return in_->options(); }
  void configure(const std::vector<hr::OptionValue>& v) override { in_->configure(v); }
  bool simulates(const hr::MaterialInfo& m) const override { return in_->simulates(m); }
  hr::Reflector reflector(const hr::MaterialInfo& m) const override { return in_->reflector(m); }
  void limitDirectionalLevels(int levels) override { in_->limitDirectionalLevels(levels); }
  void memoryBudget(std::size_t bytes) override { in_->memoryBudget(bytes); }
  std::size_t heldBytes() const override { return in_->heldBytes(); }
  void attach(const hr::HostView& v) override { in_->attach(v); }
  void split(hr::NodeId p, std::span<const hr::NodeId> c) override { in_->split(p, c); }
  // Also read of a loaded solution's cells (inspect's lobe): a cell's share of its leaf's.
  hr::Rgb intensity(hr::NodeId n, const hr::Vec3& d) const override {
    return isCell(n) ? cellShare_[n.index()] * in_->intensity(leafOf(n), d) : in_->intensity(n, d);
  }
  hr::Rgb meanIntensity(hr::NodeId n, std::span<const hr::Vec3> p) const override { return in_->meanIntensity(n, p); }
  hr::Rgb intensityBound(hr::NodeId n, const hr::Vec3& a, double c) const override { return in_->intensityBound(n, a, c); }
  hr::Rgb totalPower(hr::NodeId n) const override { return in_->totalPower(n); }
  void gather(hr::NodeId r, std::span<const hr::IncidentSample> s) override { in_->gather(r, s); }
  bool reflectsInGather() const override { return in_->reflectsInGather(); }
  void reflect(hr::NodeId l, std::span<const hr::IncidentSample> s) override { in_->reflect(l, s); }
  void pull(hr::NodeId n, std::span<const hr::NodeId> c) override { in_->pull(n, c); }
  double powerChange() const override { return in_->powerChange(); }
  bool canShoot() const override { return in_->canShoot(); }
  hr::Rgb unshotIntensity(hr::NodeId n, const hr::Vec3& d) const override { return in_->unshotIntensity(n, d); }
  hr::Rgb unshotMeanIntensity(hr::NodeId n, std::span<const hr::Vec3> p) const override {
    return in_->unshotMeanIntensity(n, p);
  }
  hr::Rgb unshotIntensityBound(hr::NodeId n, const hr::Vec3& a, double c) const override {
    return in_->unshotIntensityBound(n, a, c);
  }
  hr::Rgb unshotPower(hr::NodeId n) const override { return in_->unshotPower(n); }
  void reflectShot(hr::NodeId l, std::span<const hr::IncidentSample> s) override { in_->reflectShot(l, s); }
  std::size_t reflectShared(hr::NodeId e, std::span<hr::IncidentSample> s) override { return in_->reflectShared(e, s); }
  void shot(hr::NodeId n) override { in_->shot(n); }
  // Also read per cell for solution.vtp and inspect: a cell's share of its leaf's power, so the
  // cells of a leaf sum to it (the cell id read as a leaf id gave another leaf's power).
  hr::Rgb reflectedPower(hr::NodeId l) const override {
    return isCell(l) ? cellShare_[l.index()] * in_->reflectedPower(leafOf(l)) : in_->reflectedPower(l);
  }
  hr::Rgb sampleExitant(hr::NodeId l, double u1, double u2, hr::Vec3& d) const override {
    return in_->sampleExitant(l, u1, u2, d);
  }

  // Display and the file: solution element i is cell i, which shows its leaf's light from its own
  // side only (a cell of a curved leaf may face away from directions the leaf faces).
  hr::Rgb radiance(hr::NodeId c, const hr::Vec3& e) const override {
    return isCell(c) ? radiance(c, e, cellNormal_[c.index()]) : hr::Rgb(0.0);
  }
  hr::Rgb radiance(hr::NodeId c, const hr::Vec3& e, const hr::Vec3& n) const override {
    if (!isCell(c) || !(glm::dot(cellNormal_[c.index()], e) > 0.0)) return hr::Rgb(0.0);
    return in_->radiance(hr::NodeId{cellLeaf_[c.index()]}, e, n);
  }
  hr::Rgb radiance(hr::NodeId c, const hr::Vec3& e, const hr::Vec3& n, const hr::Vec3& at) const override {
    if (!isCell(c) || !(glm::dot(cellNormal_[c.index()], e) > 0.0)) return hr::Rgb(0.0);
    return in_->radiance(hr::NodeId{cellLeaf_[c.index()]}, e, n == hr::Vec3(0.0) ? cellNormal_[c.index()] : n, at);
  }
  /// The coefficients of the leaf a cell shows (shared by all its cells).
  std::size_t coefficients(hr::NodeId c) const override { return isCell(c) ? in_->coefficients(hr::NodeId{cellLeaf_[c.index()]}) : 0; }
  std::uint32_t formatVersion() const override { return in_->formatVersion(); }
  void save(std::ostream& out) const override {
    put32(out, kMagic);
    put32(out, H_);
    put32(out, std::uint32_t(cellLeaf_.size()));
    for (std::uint32_t l : cellLeaf_) put32(out, l);
    put32(out, std::uint32_t(shown_.size()));
    for (const auto& [id, i] : shown_) {
      put32(out, id);
      put64(out, i.area);
      for (int k = 0; k < 3; ++k) put64(out, i.normal[k]);
      put32(out, i.material);
    }
    in_->save(out);
  }
  void load(std::string_view bytes, const hr::HostView& cells) override {
    Reader r{bytes};
    const std::uint32_t magic = r.u32();
    if (magic == kOldMagic) refuse("written before cells shared their leaf's light (a copy per cell): solve the scene again");
    if (magic != kMagic) refuse("not written by this host's adapter");
    const std::uint32_t H = r.u32(), C = r.u32();
    if (std::uint64_t(H) >= hr::NodeId::kClusterBit) refuse("leaf count out of range");
    if (C != cells.elementCount())
      refuse(std::to_string(C) + " cells, the solution has " + std::to_string(cells.elementCount()) + " elements");
    if (std::uint64_t(C) * 4 > bytes.size() - r.at) refuse("truncated");
    std::vector<std::uint32_t> cellLeaf(C);
    for (std::uint32_t& l : cellLeaf)
      if ((l = r.u32()) >= H) refuse("a cell names leaf " + std::to_string(l) + " of " + std::to_string(H));
    const std::uint32_t K = r.u32();
    if (std::uint64_t(K) * 36 > bytes.size() - r.at) refuse("truncated");
    std::vector<std::pair<std::uint32_t, hr::NodeInfo>> shown(K);
    for (std::uint32_t k = 0; k < K; ++k) {
      auto& [id, i] = shown[k];
      id = r.u32();
      i.area = r.f64();
      for (int c = 0; c < 3; ++c) i.normal[c] = r.f64();
      i.material = r.u32();
      const std::string where = "leaf " + std::to_string(id);
      if (id >= H || (k > 0 && id <= shown[k - 1].first)) refuse(where + ": out of range or out of order");
      if (!(i.area > 0.0) || !std::isfinite(i.area) || !hr::allFinite(i.normal) || std::abs(glm::length(i.normal) - 1.0) > 1e-6)
        refuse(where + ": area or normal out of range");
      if (i.material >= cells.materialCount()) refuse(where + ": no material " + std::to_string(i.material));
      i.leaf = i.planar = true;  // reflected about its one normal, as a flat leaf is
    }
    std::vector<hr::Vec3> normals(C);
    for (std::uint32_t c = 0; c < C; ++c) normals[c] = cells.info(hr::NodeId{c}).normal;
    auto view = std::make_unique<LeafView>(cells, H, shown);
    in_->load(bytes.substr(r.at), *view);  // throws before anything of this adapter changes
    H_ = H, cellLeaf_ = std::move(cellLeaf), cellNormal_ = std::move(normals), shown_ = std::move(shown);
    cellShare_ = areaShares(cells, cellLeaf_, H_);
    leaves_ = std::move(view);
    showing_ = true;
  }
  std::vector<hr::StatEntry> stats() const override { return in_->stats(); }

 private:
  bool isCell(hr::NodeId c) const { return showing_ && !c.isCluster() && c.index() < cellLeaf_.size(); }
  hr::NodeId leafOf(hr::NodeId c) const { return hr::NodeId{cellLeaf_[c.index()]}; }
  /// Per cell: its area over the summed area of its leaf's cells (flat chords of a curved leaf).
  static std::vector<double> areaShares(const hr::HostView& cells, const std::vector<std::uint32_t>& cellLeaf, std::uint32_t H) {
    std::vector<double> leafArea(H, 0.0), share(cellLeaf.size(), 0.0);
    for (std::uint32_t c = 0; c < cellLeaf.size(); ++c) leafArea[cellLeaf[c]] += cells.info(hr::NodeId{c}).area;
    for (std::uint32_t c = 0; c < cellLeaf.size(); ++c)
      if (leafArea[cellLeaf[c]] > 0.0) share[c] = cells.info(hr::NodeId{c}).area / leafArea[cellLeaf[c]];
    return share;
  }
  std::unique_ptr<hr::Extension> in_;
  std::uint32_t H_ = 0;
  bool showing_ = false;  // false while solving: ids are the host's
  std::vector<std::uint32_t> cellLeaf_;  // per cell: the host leaf it shows
  std::vector<hr::Vec3> cellNormal_;     // per cell: its flat polygon's normal
  std::vector<double> cellShare_;        // per cell: its share of its leaf's light (areaShares)
  std::vector<std::pair<std::uint32_t, hr::NodeInfo>> shown_;  // the simulated leaves cells show, by id
  std::unique_ptr<LeafView> leaves_;     // loaded: the extension's view
};

}  // namespace

std::unique_ptr<hr::Extension> adapt(std::unique_ptr<hr::Extension> inner) {
  return inner ? std::make_unique<Adapter>(std::move(inner)) : nullptr;
}

void showCells(hr::Extension& ext, const hr::HostView& host, const hr::Solution& sol, const std::vector<std::uint32_t>& cellLeaf) {
  dynamic_cast<Adapter&>(ext).show(host, sol, cellLeaf);
}

}  // namespace adapters::vision
