// Radiance Clustering (Sillion, Drettakis and Soler 1995) as the paper ran it in BRIGHT (§2.2, §6.1),
// the baseline Illumination Samples are measured against (Tables 2 and 3). During gather, each link's
// contribution is pushed at once down to every simulated leaf under its receiver (one descent per
// sample), reflected there on its own and projected into the leaf's second, "new" distribution (added
// to what that holds by the re-projection the pull uses). When the host's push reaches the leaf (this
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

  struct RcCounters;
  Table fresh_;                        // per element: the "new" distribution this pass gathers
  std::vector<std::uint8_t> simulated_;  // per node (elements, then clusters): see simulatedBelow
  double heldAtAttach_ = 0.0;          // coefficients held when the pass's gather began
  std::unique_ptr<RcCounters> rc_;
};

}  // namespace glossy
