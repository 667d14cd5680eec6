// The Illumination Samples algorithm (paper §3.2-3.3) as an additive extension of a diffuse
// hierarchical radiosity host, seen through hr/extension.h only. The host keeps rho_d and all of its
// light; this extension owns the rho_s lobe of glossy leaves and the directional exitant intensity
// (W/sr) of the nodes above them:
// - reflect: a glossy leaf's samples (pushed down by the host, one traversal per iteration) are
//   reflected and projected into the leaf's distribution, replacing the previous one (Jacobi);
// - pull: inner elements and clusters hold the sum of their children's distributions (Haar trees
//   re-projected with the same refiner so that sums do not grow into unions; power exact);
// - sending, the oracle, the energy audit, display and the solution file read those distributions.
// Planar nodes keep Haar distributions in their own frame (normal = +z), so the horizon is a cell
// boundary; clusters keep theirs in the world frame. Per-node data live in side tables indexed by
// NodeId; a hook writes only the node it was called for.
#pragma once
#include <glossy/distribution.h>
#include <glossy/frame.h>
#include <hr/extension.h>

#include <atomic>
#include <memory>
#include <vector>

namespace glossy {

class IlluminationSamples final : public hr::Extension {
 public:
  IlluminationSamples();
  ~IlluminationSamples() override;

  std::string_view name() const override { return "is"; }
  std::vector<hr::OptionSpec> options() const override;
  void configure(const std::vector<hr::OptionValue>& values) override;
  bool simulates(const hr::MaterialInfo& m) const override;
  void attach(const hr::HostView& view) override;
  void split(hr::NodeId parent, std::span<const hr::NodeId> children) override;

  hr::Rgb intensity(hr::NodeId node, const hr::Vec3& dir) const override;
  hr::Rgb meanIntensity(hr::NodeId node, std::span<const hr::Vec3> polygon) const override;
  hr::Rgb intensityBound(hr::NodeId node, const hr::Vec3& axis, double cosHalfAngle) const override;

  void gather(hr::NodeId receiver, std::span<const hr::IncidentSample> samples) override;
  void reflect(hr::NodeId leaf, std::span<const hr::IncidentSample> samples) override;
  void pull(hr::NodeId node, std::span<const hr::NodeId> children) override;
  double powerChange() const override;

  hr::Rgb reflectedPower(hr::NodeId leaf) const override;
  hr::Rgb sampleExitant(hr::NodeId leaf, double u1, double u2, hr::Vec3& dir) const override;
  hr::Rgb radiance(hr::NodeId leaf, const hr::Vec3& toEye) const override;
  std::size_t coefficients(hr::NodeId leaf) const override;

  std::uint32_t formatVersion() const override { return 1; }
  std::string save() const override;
  void load(std::string_view bytes, const hr::HostView& view) override;
  std::vector<hr::StatEntry> stats() const override;

  const BasisSpec& basis() const { return basis_; }

  /// One node's directional exitant light.
  struct NodeLight {
    AnyDistribution dist;
    Frame frame;            // the orientation dist is stored in
    Vec3 normal{0.0};       // unit world normal of a planar node: nothing leaves below it; zero otherwise
    double area = 0.0;      // m^2
    Rgb power{0.0};         // W: Haar, the integral of what intensity() returns; else dist's integral
    Rgb peak{0.0};          // W/sr: a bound of intensity() over all directions
  };
  /// The node's light, or nullptr when it has none (diffuse, dark, or not yet reflected/pulled).
  const NodeLight* light(hr::NodeId node) const;

 private:
  std::unique_ptr<NodeLight>* slot(hr::NodeId node);
  /// Whether element i is a leaf of the attached view (display and the file need leaves only).
  bool isLeaf(std::size_t i) const;
  void finish(NodeLight& l) const;
  void resize(std::size_t elements, std::size_t clusters);

  struct Counters;
  BasisSpec basis_;
  const hr::HostView* view_ = nullptr;
  std::vector<std::unique_ptr<NodeLight>> elements_, clusters_;
  std::vector<Rgb> change_;  // per element, W: |power change| of the latest reflect (leaves)
  std::unique_ptr<Counters> counters_;
};

}  // namespace glossy
