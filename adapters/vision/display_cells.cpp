// The VISION-like host's display cells for an unchanged extension (see display_cells.h). The cells
// become children of their leaves in a view that numbers them after the host's H nodes (cell i is
// node H + i), and the extension's own split hook hands each leaf's light down to them (an intensity
// in W/sr scales with area). Solution element i is then node H + i for display and the file. The
// saved section is a small header (magic, H) and the extension's own bytes; loading rebuilds the
// same numbering over the loaded solution, so `render` and the viewer need nothing of the host.
#include "display_cells.h"

#include <hr/solution_view.h>

#include <cstring>
#include <ostream>
#include <optional>

namespace adapters::vision {
namespace {

constexpr std::uint32_t kMagic = 0x43534956u;  // "VISC"
constexpr const char* kWhat = "solution file, section of the extension on the VISION-like host";

/// Nodes 0..H-1: the host's (none of them a leaf of the display); H + i: solution element i. The
/// cells are read from a view of the solution (loading), or copied from one (solving: the solution
/// may move before the outputs are written).
class CellView final : public hr::HostView {
 public:
  CellView(const hr::HostView* host, const hr::HostView& cells, std::uint32_t H, bool copy) : host_(host), cells_(&cells), H_(H) {
    if (!copy) return;
    for (std::uint32_t i = 0; i < cells.elementCount(); ++i) info_.push_back(cells.info(hr::NodeId{i}));
    for (std::uint32_t m = 0; m < cells.materialCount(); ++m) materials_.push_back(cells.material(m));
    cells_ = nullptr;
  }
  /// The runs of cells of each leaf (cellLeaf: per cell, its leaf; a leaf's cells are consecutive).
  void setCells(const std::vector<std::uint32_t>& cellLeaf) {
    first_.assign(H_, hr::kNone), count_.assign(H_, 0);
    for (std::uint32_t i = 0; i < cellLeaf.size(); ++i) {
      ids_.push_back(hr::NodeId{H_ + i});
      const std::uint32_t l = cellLeaf[i];
      if (l >= H_) throw hr::InputError("display cell " + std::to_string(i) + " names no leaf of the host");
      if (first_[l] == hr::kNone) first_[l] = i;
      if (first_[l] + count_[l] != i) throw hr::InputError("the cells of leaf " + std::to_string(l) + " are not consecutive");
      ++count_[l];
    }
  }
  std::span<const hr::NodeId> cellsOf(std::uint32_t leaf) const {
    return leaf < first_.size() && count_[leaf] ? std::span<const hr::NodeId>(ids_.data() + first_[leaf], count_[leaf])
                                                : std::span<const hr::NodeId>();
  }
  hr::NodeId root() const override { return host_ ? host_->root() : hr::NodeId{H_}; }
  hr::NodeInfo info(hr::NodeId n) const override {
    if (n.isCluster()) return host_ ? host_->info(n) : hr::NodeInfo{};
    if (n.index() >= H_) return cells_ ? cells_->info(hr::NodeId{n.index() - H_}) : info_.at(n.index() - H_);
    hr::NodeInfo i = host_ ? host_->info(n) : hr::NodeInfo{};
    i.leaf = false;  // shown by its cells
    return i;
  }
  std::span<const hr::NodeId> children(hr::NodeId n) const override {
    if (!n.isCluster() && n.index() >= H_) return {};
    if (!n.isCluster() && !cellsOf(n.index()).empty()) return cellsOf(n.index());
    return host_ ? host_->children(n) : std::span<const hr::NodeId>();
  }
  std::size_t elementCount() const override { return H_ + (cells_ ? cells_->elementCount() : info_.size()); }
  std::size_t clusterCount() const override { return host_ ? host_->clusterCount() : 0; }
  hr::MaterialInfo material(std::uint32_t id) const override { return cells_ ? cells_->material(id) : materials_.at(id); }
  std::size_t materialCount() const override { return cells_ ? cells_->materialCount() : materials_.size(); }

 private:
  const hr::HostView* host_;
  const hr::HostView* cells_;
  std::vector<hr::NodeInfo> info_;
  std::vector<hr::MaterialInfo> materials_;
  const std::uint32_t H_;
  std::vector<std::uint32_t> first_, count_;
  std::vector<hr::NodeId> ids_;
};

class Adapter final : public hr::Extension {
 public:
  explicit Adapter(std::unique_ptr<hr::Extension> inner) : in_(std::move(inner)) {}

  void show(const hr::HostView& host, const hr::Solution& sol, const std::vector<std::uint32_t>& cellLeaf) {
    stats_ = in_->stats();  // the solve's figures, not the cells'
    H_ = static_cast<std::uint32_t>(host.elementCount());
    view_.emplace(&host, hr::SolutionView(sol), H_, true);
    view_->setCells(cellLeaf);
    in_->attach(*view_);
    for (std::uint32_t leaf = 0; leaf < H_; ++leaf) {
      if (view_->cellsOf(leaf).empty() || !in_->simulates(host.material(host.info(hr::NodeId{leaf}).material))) continue;
      in_->split(hr::NodeId{leaf}, view_->cellsOf(leaf));
    }
    shown_ = true;
  }

  // Solving: the host's own node ids, passed through.
  std::string_view name() const override { return in_->name(); }
  std::vector<hr::OptionSpec> options() const override { return in_->options(); }
  void configure(const std::vector<hr::OptionValue>& v) override { in_->configure(v); }
  bool simulates(const hr::MaterialInfo& m) const override { return in_->simulates(m); }
  void attach(const hr::HostView& v) override { in_->attach(v); }
  void split(hr::NodeId p, std::span<const hr::NodeId> c) override { in_->split(p, c); }
  hr::Rgb intensity(hr::NodeId n, const hr::Vec3& d) const override { return in_->intensity(n, d); }
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
  bool reflectShared(hr::NodeId e, std::span<const hr::IncidentSample> s) override { return in_->reflectShared(e, s); }
  void shot(hr::NodeId n) override { in_->shot(n); }
  hr::Rgb reflectedPower(hr::NodeId l) const override { return in_->reflectedPower(l); }
  hr::Rgb sampleExitant(hr::NodeId l, double u1, double u2, hr::Vec3& d) const override {
    return in_->sampleExitant(l, u1, u2, d);
  }

  // Display and the file: solution element i is node H + i.
  hr::Rgb radiance(hr::NodeId l, const hr::Vec3& e) const override { return in_->radiance(cell(l), e); }
  std::size_t coefficients(hr::NodeId l) const override { return in_->coefficients(cell(l)); }
  std::uint32_t formatVersion() const override { return in_->formatVersion(); }
  void save(std::ostream& out) const override {
    char bytes[8];
    const std::uint32_t head[2] = {kMagic, H_};
    for (int k = 0; k < 8; ++k) bytes[k] = char((head[k / 4] >> (8 * (k % 4))) & 0xFF);
    out.write(bytes, 8);
    in_->save(out);
  }
  void load(std::string_view bytes, const hr::HostView& cells) override {
    if (bytes.size() < 8) throw hr::InputError(std::string(kWhat) + ": truncated");
    std::uint32_t head[2] = {0, 0};
    for (int k = 0; k < 8; ++k) head[k / 4] |= std::uint32_t(static_cast<unsigned char>(bytes[std::size_t(k)])) << (8 * (k % 4));
    if (head[0] != kMagic) throw hr::InputError(std::string(kWhat) + ": not written by this host's adapter");
    if (std::uint64_t(head[1]) + cells.elementCount() >= hr::NodeId::kClusterBit)
      throw hr::InputError(std::string(kWhat) + ": node count out of range");
    H_ = head[1];
    view_.emplace(nullptr, cells, H_, false);
    in_->load(bytes.substr(8), *view_);
    shown_ = true;
  }
  std::vector<hr::StatEntry> stats() const override { return shown_ && !stats_.empty() ? stats_ : in_->stats(); }

 private:
  hr::NodeId cell(hr::NodeId n) const { return n.isCluster() ? n : hr::NodeId{n.index() + H_}; }
  std::unique_ptr<hr::Extension> in_;
  std::uint32_t H_ = 0;  // 0 while solving: ids are the host's
  bool shown_ = false;
  std::optional<CellView> view_;
  std::vector<hr::StatEntry> stats_;
};

}  // namespace

std::unique_ptr<hr::Extension> adapt(std::unique_ptr<hr::Extension> inner) {
  return inner ? std::make_unique<Adapter>(std::move(inner)) : nullptr;
}

void showCells(hr::Extension& ext, const hr::HostView& host, const hr::Solution& sol, const std::vector<std::uint32_t>& cellLeaf) {
  dynamic_cast<Adapter&>(ext).show(host, sol, cellLeaf);
}

}  // namespace adapters::vision
