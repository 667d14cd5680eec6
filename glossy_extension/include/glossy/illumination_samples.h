// The Illumination Samples algorithm (paper §3.2-3.3) as an additive extension of a diffuse
// hierarchical radiosity host, seen through hr/extension.h only. The host keeps rho_d and all of its
// light; this extension owns the rho_s lobe of glossy leaves and the directional exitant intensity
// (W/sr) of the nodes above them:
// - reflect: a glossy leaf's samples (pushed down by the host, one traversal per iteration) are
//   reflected and projected into the leaf's distribution, replacing the previous one (Jacobi);
// - pull: inner elements and clusters hold the sum of their children's distributions (Haar trees
//   re-projected with the same refiner so that sums do not grow into unions; power exact);
// - sending, the oracle, the energy audit, display and the solution file read those distributions.
// - shooting (§3.4): beside the total light every leaf keeps its unshot light; reflectShot adds a
//   pass's reflection to both, shot() clears a shooter's unshot light, pull sums the unshot light
//   (the only light hosts read above the leaves while shooting), and a node whose children did not
//   change since the last pull keeps what it has.
// Planar nodes keep Haar distributions in their own frame (normal = +z), so the horizon is a cell
// boundary; clusters keep theirs in the world frame. With --basis auto each glossy material has its own
// basis (basis_rule.h); a node above surfaces of different bases holds one sum per basis (NodeLight::more). Per-node data live in side tables indexed by
// NodeId; a hook writes only the node it was called for (shot(): its subtree).
// Radiance Clustering (radiance_clustering.h) derives from this class: it shares the exitant side
// (distributions, pull, queries, file, statistics) and replaces only how incident light is reflected.
#pragma once
#include <glossy/basis_rule.h>
#include <glossy/distribution.h>
#include <glossy/frame.h>
#include <glossy/is_options.h>
#include <glossy/reflection.h>
#include <glossy/shown_light.h>
#include <hr/extension.h>

#include <atomic>
#include <memory>
#include <vector>

namespace glossy {

class IlluminationSamples : public hr::Extension {
 public:
  IlluminationSamples();
  ~IlluminationSamples() override;

  std::string_view name() const override { return "is"; }
  std::vector<hr::OptionSpec> options() const override;
  void configure(const std::vector<hr::OptionValue>& values) override;
  bool simulates(const hr::MaterialInfo& m) const override;
  hr::Reflector reflector(const hr::MaterialInfo& m) const override;
  void attach(const hr::HostView& view) override;
  void split(hr::NodeId parent, std::span<const hr::NodeId> children) override;
  void limitDirectionalLevels(int levels) override;
  void memoryBudget(std::size_t bytes) override;
  std::size_t heldBytes() const override;

  hr::Rgb intensity(hr::NodeId node, const hr::Vec3& dir) const override;
  hr::Rgb totalPower(hr::NodeId node) const override;
  hr::Rgb meanIntensity(hr::NodeId node, std::span<const hr::Vec3> polygon) const override;
  hr::Rgb intensityBound(hr::NodeId node, const hr::Vec3& axis, double cosHalfAngle) const override;

  void gather(hr::NodeId receiver, std::span<const hr::IncidentSample> samples) override;
  void reflect(hr::NodeId leaf, std::span<const hr::IncidentSample> samples) override;
  std::size_t reflectShared(hr::NodeId element, std::span<hr::IncidentSample> samples) override;
  void pull(hr::NodeId node, std::span<const hr::NodeId> children) override;
  double powerChange() const override;

  bool canShoot() const override { return true; }
  hr::Rgb unshotIntensity(hr::NodeId node, const hr::Vec3& dir) const override;
  hr::Rgb unshotMeanIntensity(hr::NodeId node, std::span<const hr::Vec3> polygon) const override;
  hr::Rgb unshotIntensityBound(hr::NodeId node, const hr::Vec3& axis, double cosHalfAngle) const override;
  hr::Rgb unshotPower(hr::NodeId node) const override;
  void reflectShot(hr::NodeId leaf, std::span<const hr::IncidentSample> samples) override;
  void shot(hr::NodeId node) override;

  hr::Rgb reflectedPower(hr::NodeId leaf) const override;
  hr::Rgb sampleExitant(hr::NodeId leaf, double u1, double u2, hr::Vec3& dir) const override;
  hr::Rgb radiance(hr::NodeId leaf, const hr::Vec3& toEye) const override;
  hr::Rgb radiance(hr::NodeId leaf, const hr::Vec3& toEye, const hr::Vec3& normal) const override;
  hr::Rgb radiance(hr::NodeId leaf, const hr::Vec3& toEye, const hr::Vec3& normal, const hr::Vec3& at) const override;
  std::size_t coefficients(hr::NodeId leaf) const override;

  std::uint32_t formatVersion() const override { return 6; }
  void save(std::ostream& out) const override;
  void load(std::string_view bytes, const hr::HostView& view) override;
  std::vector<hr::StatEntry> stats() const override;

  const BasisSpec& basis() const { return basis_; }
  /// The basis the leaves of material `id` are projected in (the configured one, or auto's choice);
  /// valid after attach or load.
  Basis materialBasis(std::uint32_t id) const;
  /// The finest Haar level the leaves of material `id` are refined to: --dir-max-level when given,
  /// else from its lobe's width (lobe_level.h); either held lower by a memory budget. Valid after attach.
  int materialLevel(std::uint32_t id) const;

  /// One node's directional exitant light.
  struct NodeLight {
    AnyDistribution dist;
    Frame frame;            // the orientation dist is stored in
    Vec3 normal{0.0};       // unit world normal of a planar node: nothing leaves below it; zero otherwise
    double area = 0.0;      // m^2
    Rgb power{0.0};         // W: Haar, the integral of what intensity() returns; else dist's integral
    Rgb peak{0.0};          // W/sr: a bound of intensity() over all directions
    /// A node whose subtree mixes bases (--basis auto): its light in each further basis, summed
    /// exactly within that basis, never re-projected into another (a sharp Haar lobe would smear in
    /// spherical harmonics, a broad one cost Haar cells and power exactness). Parts hold no parts.
    std::vector<NodeLight> more;
    /// A leaf's brightest incident samples, for the display only (shown_light.h); shared by copies.
    std::shared_ptr<const ShownLight> shown;
    Rgb totalPower() const;
    std::size_t totalCoefficients() const;
  };
  /// The node's light, or nullptr when it has none (diffuse, dark, or not yet reflected/pulled).
  const NodeLight* light(hr::NodeId node) const;
  /// The node's unshot light (shooting), or nullptr.
  const NodeLight* unshotLight(hr::NodeId node) const;

 protected:
  using Table = std::vector<std::unique_ptr<NodeLight>>;
  std::unique_ptr<NodeLight>* slot(Table& elements, Table& clusters, hr::NodeId node);
  std::unique_ptr<NodeLight>* slot(hr::NodeId node) { return slot(elements_, clusters_, node); }
  /// A light's intensity toward unit dir and its mean over a spherical polygon, W/sr (what
  /// intensity/meanIntensity and their unshot kin return; a null light sends nothing).
  static hr::Rgb intensityOf(const NodeLight* l, const hr::Vec3& dir);
  static hr::Rgb meanIntensityOf(const NodeLight* l, std::span<const hr::Vec3> polygon);
  /// The same of one part alone (a light's `more` not included).
  static hr::Rgb intensityOfPart(const NodeLight& l, const hr::Vec3& dir);
  static hr::Rgb meanIntensityOfPart(const NodeLight& l, std::span<const hr::Vec3> polygon);
  /// Whether element i is a leaf of the attached view (display and the file need leaves only).
  bool isLeaf(std::size_t i) const;
  void finish(NodeLight& l) const;
  /// Chooses the basis of every material of the view (attach, load).
  void chooseBases(const hr::HostView& view);
  /// Each material's finest Haar level (chooseBases calls it; the budget's steering too).
  void chooseLevels(const hr::HostView& view);
  /// The level of a material of Phong exponent n under the options and the budget.
  int levelFor(double exponent) const;
  /// The sum of lights that all hold one basis, as `node`'s light in that basis.
  NodeLight sumOneBasis(hr::NodeId node, Basis b, std::span<const NodeLight* const> parts) const;
  /// Radiance toward the eye seen at normal (zero: the leaf's own), with the shown light re-aimed
  /// from *at when given (is_queries.cpp).
  hr::Rgb radianceAt(hr::NodeId leaf, const hr::Vec3& toEye, const hr::Vec3& normal, const hr::Vec3* at) const;
  /// Reads the solution file's shown light into the leaves of `table` (is_file.cpp).
  void readShown(std::istream& in, Table& table) const;
  /// Sizes every per-node table (they only grow).
  virtual void resize(std::size_t elements, std::size_t clusters);
  /// A leaf's reflection of some samples as a light of its own (frame, area, normal), or nullptr when
  /// they bring no light to its front; counts what it did. With `shared`, the reflection its
  /// ancestors took for it (reflectShared) joins its own samples'.
  std::unique_ptr<NodeLight> reflected(hr::NodeId leaf, std::span<const hr::IncidentSample> samples,
                                       bool shared = false);
  /// The sum of lights as `node`'s light (its frame, or the world frame for a cluster whose parts
  /// disagree), or nullptr when every part is null.
  std::unique_ptr<NodeLight> sum(hr::NodeId node, std::span<const NodeLight* const> parts) const;
  /// Marks a node's light changed since its parent's last pull.
  void touch(hr::NodeId node);
  /// Coefficients held in every distribution now (the statistics' peak is taken from this).
  virtual double held() const;
  /// Raises the peak of coefficients held to `now` (serial hooks only: attach; stats adds the end).
  void notePeak(double now);

  struct Counters;
  BasisSpec basis_;
  std::vector<Basis> materialBasis_;  // per material of the view
  std::vector<std::pair<double, AutoChoice>> autoChoices_;  // by exponent: measured once per solve
  const hr::HostView* view_ = nullptr;
  Table elements_, clusters_;
  Table unshotElements_, unshotClusters_;     // shooting only
  std::atomic<bool> shooting_{false};         // a shot() came: pull keeps no total above the leaves
  std::vector<std::uint8_t> dirtyElements_, dirtyClusters_;  // changed since the parent's last pull
  std::vector<Rgb> change_;  // per element, W: |power change| of the latest reflect (leaves)
  // Reflection in layers (reflectShared): per inner element that took its samples this sweep, the cell
  // sums per unit area of its own and its ancestors' shared samples (freed by its pull); per element,
  // the element whose sums reach it from above, or hr::kNone.
  std::vector<std::unique_ptr<HaarCellSums>> layers_;
  std::vector<std::shared_ptr<const ShownLight>> layerShown_;  // per layer: its shown light and its ancestors'
  std::vector<std::uint32_t> layerFrom_;
  std::unique_ptr<Counters> counters_;
  double peakHeld_ = 0.0;
  int finestLevel_;  // the given --dir-max-level, else the lobe rule's finest; no material's level exceeds it
  int budgetLevels_ = -1;  // the memory budget's levels above dir-min-level (limitDirectionalLevels), -1: none
  std::vector<int> materialLevel_;  // per material of the view, -1 for one not simulated
  int pullFloor_ = 3;  // the coarsest Haar material's level: sums are never projected coarser
  ReflectionRefine refineReflections_ = ReflectionRefine::Lobe;  // --reflection-refine: what reflector() reports
  int senderPoints_ = kSenderPoints;  // --sender-extent: directions a wide sender is spread over (0: off)
  bool exactHighlights_ = true;        // --exact-highlights: leaves keep their shown light (shown_light.h)
};

}  // namespace glossy
