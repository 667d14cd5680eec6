// Radiance Clustering (Sillion, Drettakis and Soler 1995) as the paper ran it in BRIGHT (§2.2, §6.1),
// the baseline Illumination Samples are measured against (Tables 2 and 3). During gather, each link's
// contribution is pushed at once down to every simulated leaf under its receiver (one descent per
// sample), reflected there on its own and projected into the leaf's second, "new" distribution. The
// paper projects each reflection response separately and adds it into the leaf's function (§2.2, §3.1),
// so by default the sum is exact, on the union of the two trees (--rc-add exact); --rc-add recut
// re-projects the running sum with the relative refiner at every sample instead, as the pull sums
// (fewer coefficients, and a variation below the threshold of the sum so far is dropped for good). When the host's push reaches the leaf (this
// extension reflects in gather, so the host carries no samples), the new distribution becomes the
// leaf's light and the old one is dropped; the pull then sums upward as for Illumination Samples.
// It derives from IlluminationSamples and shares everything else with it: options and bases, the
// projection of a lobe (projectLobes), the relative refiner, the pull, sending, bounds, energy,
// display, file and statistics. Only the handling of incident light differs, which is what the paper
// compares. Gathering only (canShoot is false): the paper ran it so.
#pragma once
#include <glossy/illumination_samples.h>

namespace glossy {

class RadianceClustering final : public IlluminationSamples {
 public:
  RadianceClustering();
  ~RadianceClustering() override;

  std::string_view name() const override { return "rc"; }
  bool canShoot() const override { return false; }
  bool reflectsInGather() const override { return true; }
  std::vector<hr::OptionSpec> options() const override;
  void configure(const std::vector<hr::OptionValue>& values) override;
  void attach(const hr::HostView& view) override;
  void gather(hr::NodeId receiver, std::span<const hr::IncidentSample> samples) override;
  void reflect(hr::NodeId leaf, std::span<const hr::IncidentSample> samples) override;
  std::vector<hr::StatEntry> stats() const override;

 protected:
  void resize(std::size_t elements, std::size_t clusters) override;
  double held() const override;

 private:
  /// Carries one sample down from node to the simulated leaves below it; `planar`: its irradiance
  /// already lies on the node's plane (an element receiver's), else it is E_perp (a cluster's).
  void push(hr::NodeId node, hr::IncidentSample sample, bool planar);
  /// Whether a node's subtree holds a surface this extension simulates (computed at attach).
  bool simulatedBelow(hr::NodeId node) const;
  std::uint8_t markSimulated(hr::NodeId node);
  /// target += add exactly when both hold one distribution of one basis in one frame (a leaf's own);
  /// false otherwise (--basis auto's parts), where the caller sums by re-projection.
  bool addExactly(NodeLight& target, const NodeLight& add) const;

  struct RcCounters;
  Table fresh_;                        // per element: the "new" distribution this pass gathers
  std::vector<std::uint8_t> simulated_;  // per node (elements, then clusters): see simulatedBelow
  bool recut_ = false;                 // --rc-add recut
  double heldAtAttach_ = 0.0;          // coefficients held when the pass's gather began
  std::unique_ptr<RcCounters> rc_;
};

}  // namespace glossy
