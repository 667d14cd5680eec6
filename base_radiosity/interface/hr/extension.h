// The whole interface an extension sees of a radiosity host (with hr/host_view.h): four hook points,
// link gather, push/pull, reflection and display, plus what the oracle, the energy audit, the
// solution file and the command line need. The contract is additive: the host keeps the Lambertian
// part of every surface and all of its light; an extension owns only the part it simulates (e.g. the
// specular lobe) and the host adds that share wherever it reads exitant light, a bound, a residual,
// an energy term or a display value. Every hook has an empty default and a run without an extension
// calls none. Calls are per phase, per receiver, per node or per leaf, never per ray. Extension data
// lives in the extension's own arrays indexed by NodeId.
#pragma once
#include <hr/host_view.h>
#include <hr/sender_shape.h>

#include <algorithm>
#include <cmath>
#include <iosfwd>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hr {

/// An Illumination Sample: the light one link brought to a node this iteration. At an element,
/// `irradiance` lies on the element's plane; at a cluster it is E_perp, on a surface facing the sender.
struct IncidentSample {
  Vec3 toSender{0.0};    // unit, receiver -> sender
  Rgb irradiance{0.0};   // W/m^2, visibility included
  double distance = 0.0;  // m, to the sender's centre from where toSender was taken; 0: unknown
  double radius = 0.0;    // m, the sender's extent about its centre (a disk of its second moment); 0: a point
  // Unit normal of a flat sender, zero for a cluster, a curved or an unknown one: a display that
  // carries the irradiance to another point of the receiver needs the sender's foreshortening there
  // too (a tilted lamp 2 m off is 3 % brighter seen from 10 cm nearer its axis). Floats: hosts hold many.
  glm::vec3 senderNormal{0.0f};
  // And its shape, where senderNormal is set: the rectangle of its second moments in its plane
  // (hr/sender_shape.h; axis zero: none known, a disk of `radius`), so a highlight takes the source's
  // shape. Only a display reads it.
  SenderRectangle senderShape{};
};

/// IncidentSample::radius of a sender whose surface has mean squared distance spread2 (m^2) from its
/// centre, seen at cosine c to its normal: the disk of the same second moment as its projection (a
/// flat sender's isotropic spread2 / 2 per axis, one axis foreshortened by c), so a face seen
/// edge-on is still a line's width, not a point.
inline double senderDiskRadius(double spread2, double c) {
  return spread2 > 0.0 && std::isfinite(spread2) ? std::sqrt(spread2 * (1.0 + std::min(1.0, c * c))) : 0.0;
}

/// A sample taken at `from` as seen from `to` (a host carrying it down to a child): it points at the
/// same sender centre, since a child far from its ancestor's centre sees a near sender elsewhere
/// (parallax). Its irradiance stays the link's, so no light is made or lost. Unknown distance: as is.
inline void aimFrom(IncidentSample& s, const Vec3& from, const Vec3& to) {
  if (!(s.distance > 0.0)) return;
  const Vec3 d = from + s.distance * s.toSender - to;
  const double len = glm::length(d);
  if (len > 0.0) s.toSender = d / len, s.distance = len;
}

/// How sharply a simulated material reflects, for the host's oracle: the share of incident light its
/// lobe sends on (luminance, at most 1) and the lobe's angular half-width, rad. An Illumination Sample
/// carries one direction per link (receiver to the sender's centre) and every receiver leaf reflects
/// it as one lobe over its whole area, so a link whose sender is seen wider than the lobe, or whose
/// receiver sees the sender from directions further apart than the lobe, blurs and misplaces the
/// reflected image (a mirror's reflection of a near object came out as blobs). Albedo 0: no term.
struct Reflector {
  double albedo = 0.0;
  double width = 0.0;
};

/// A reflector as a host's oracle takes it: one that is empty, not finite or of no width asks nothing.
inline Reflector usableReflector(const Reflector& r) {
  return r.albedo > 0.0 && std::isfinite(r.albedo) && r.width > 0.0 && std::isfinite(r.width) ? r : Reflector{};
}
/// A cluster's bound over its parts: the largest albedo and the narrowest lobe of a and b.
inline void keepSharpest(Reflector& a, const Reflector& b) {
  if (!(b.albedo > 0.0)) return;
  a.albedo = std::max(a.albedo, b.albedo);
  a.width = std::min(a.width, b.width);
}

/// The share of a link's received power (W) that a host's oracle counts as misplaced by such a
/// receiver: reach is twice the larger node's radius, d the distance between the nodes' centres.
/// The fraction (1 - width d / reach) of the reflected power is taken as misplaced, weighed by
/// width^-2 (a lobe sends it into about pi width^2, where a Lambertian receiver spreads it over pi).
inline double misplacedReflection(const Reflector& r, double reach, double d) {
  if (!(r.albedo > 0.0) || reach <= r.width * d) return 0.0;
  const double misplaced = d > 0.0 ? 1.0 - r.width * d / reach : 1.0;
  return r.albedo * misplaced / std::min(1.0, r.width * r.width);
}

struct OptionSpec {
  std::string name;  // without dashes, e.g. "dir-eps"
  std::string help;
};
struct OptionValue {
  std::string name, value;
};
struct StatEntry {
  std::string name;  // a key of stats.json's "extension" object
  double value = 0.0;
  std::string text;  // when not empty the entry is this text (a choice, e.g. a basis), not value
  StatEntry() = default;
  StatEntry(std::string n, double v) : name(std::move(n)), value(v) {}
  StatEntry(std::string n, std::string t) : name(std::move(n)), text(std::move(t)) {}
};

class Extension {
 public:
  virtual ~Extension() = default;
  virtual std::string_view name() const = 0;

  // Set-up: serial.
  /// Options the command line passes through; any other option given with this extension is refused.
  virtual std::vector<OptionSpec> options() const { return {}; }
  /// Applies the options given; throws InputError naming the option for a bad value. Once, first.
  virtual void configure(const std::vector<OptionValue>&) {}
  /// Whether the extension simulates a part of this material; samples reach only such subtrees.
  virtual bool simulates(const MaterialInfo&) const { return false; }
  /// How sharply a material it simulates reflects (Reflector); the default asks no refinement.
  virtual Reflector reflector(const MaterialInfo&) const { return {}; }
  /// The node set changed (after every refinement pass): size side tables. Serial.
  virtual void attach(const HostView&) {}
  /// A leaf was split into children (already readable in the view): hand its light down so a new
  /// sender is never dark. Serial.
  virtual void split(NodeId /*parent*/, std::span<const NodeId> /*children*/) {}

  /// A memory budget (the host's --memory-mb) allows `levels` levels of directional subdivision above
  /// the extension's coarsest, or its configured finest when levels < 0: directional detail follows
  /// the spatial threshold the budget has reached, so a tight budget does not spend its memory on
  /// fine lobes over coarse elements. Serial, before a pass; never called without a budget.
  virtual void limitDirectionalLevels(int /*levels*/) {}
  /// A memory budget holds the whole process to `bytes`: an extension sizes what it keeps for speed
  /// alone (caches) from it, since the budget steers by the memory it has seen and a cache grows
  /// when it will. Serial, once before the first pass; never called without a budget.
  virtual void memoryBudget(std::size_t /*bytes*/) {}
  /// Bytes the extension's data hold now: a memory budget reserves what writing them out (solution
  /// file, display) will cost. Serial, between passes.
  virtual std::size_t heldBytes() const { return 0; }

  // Sending: const, concurrent with each other, never during the phases below.
  /// The extension's share of a node's exitant radiant intensity toward unit dir, W/sr.
  virtual Rgb intensity(NodeId, const Vec3& /*dir*/) const { return Rgb(0.0); }
  /// Its whole exitant power, W per channel: what a link carries whose direction means nothing (a
  /// sender inside the cluster it lights). The total-light kin of unshotPower.
  virtual Rgb totalPower(NodeId) const { return Rgb(0.0); }
  /// Its mean over a convex spherical polygon of unit directions (the receiver seen from the node):
  /// what a link delivers to an extended receiver; a narrow lobe must not be sampled at a few points.
  virtual Rgb meanIntensity(NodeId n, std::span<const Vec3> polygon) const {
    Vec3 c(0.0);
    for (const Vec3& d : polygon) c += d;
    return glm::length(c) > 0.0 ? intensity(n, glm::normalize(c)) : Rgb(0.0);
  }
  /// An upper bound of that share within acos(cosHalfAngle) of unit axis: the oracle's sight of highlights.
  virtual Rgb intensityBound(NodeId, const Vec3& /*axis*/, double /*cosHalfAngle*/) const { return Rgb(0.0); }

  // Link gather: top-down, concurrent across disjoint subtrees; a receiver is always called after every
  // receiver above it, so a gather may write the simulated leaves below its receiver.
  /// A receiver whose subtree holds simulated surfaces, with the samples its links brought this iteration.
  virtual void gather(NodeId /*receiver*/, std::span<const IncidentSample>) {}
  /// True if gather() reflects the samples itself (immediate push, Radiance Clustering): the host then
  /// carries no samples down and calls reflect() with none. Serial, once.
  virtual bool reflectsInGather() const { return false; }

  // Reflection: during the host's push, concurrent across leaves.
  /// Every simulated leaf every iteration, with all its samples (its own and its ancestors', on its
  /// plane; possibly none) but those an ancestor's reflectShared took: its light replaces the
  /// previous iteration's.
  virtual void reflect(NodeId /*leaf*/, std::span<const IncidentSample>) {}
  /// Optional, gathering or a shooting pass: an inner element of a simulated planar subtree with the
  /// samples that reached it there (its own links', and at the top of a surface those of the clusters
  /// above), before its children. Reflection is linear, so an extension may reflect once for the whole
  /// subtree the samples every leaf below would reflect alike (a sender far enough that the subtree
  /// sees it in one direction): it moves those it took to the back and returns how many it left in
  /// front, which the host carries down, each re-aimed from the child it reaches (parallax).
  /// Top-down, concurrent across disjoint subtrees; the default takes none.
  virtual std::size_t reflectShared(NodeId /*element*/, std::span<IncidentSample> samples) { return samples.size(); }

  // Push/pull: children before parents, concurrent across disjoint subtrees.
  /// An inner element or cluster above simulated leaves: its exitant light from its children's, the
  /// total while gathering, the unshot light while shooting (a shooting host reads no other light
  /// above the leaves, so an extension need keep no total there).
  virtual void pull(NodeId /*node*/, std::span<const NodeId> /*children*/) {}
  /// After the pull: how much the extension's exitant power changed this iteration, W (luminance).
  virtual double powerChange() const { return 0.0; }

  // Shooting (the host's --iteration shoot, paper §3.4): the extension keeps unshot light beside its
  // total light. A host asks canShoot() first and refuses to shoot with an extension that cannot.
  /// Whether the hooks below are implemented. Serial, once.
  virtual bool canShoot() const { return false; }
  /// The unshot share of a node's exitant intensity toward unit dir, W/sr (what a shooter sends). Const,
  /// concurrent (as intensity()).
  virtual Rgb unshotIntensity(NodeId, const Vec3& /*dir*/) const { return Rgb(0.0); }
  /// Its mean over a convex spherical polygon of unit directions (as meanIntensity).
  virtual Rgb unshotMeanIntensity(NodeId n, std::span<const Vec3> polygon) const {
    Vec3 c(0.0);
    for (const Vec3& d : polygon) c += d;
    return glm::length(c) > 0.0 ? unshotIntensity(n, glm::normalize(c)) : Rgb(0.0);
  }
  /// An upper bound of that share within acos(cosHalfAngle) of unit axis (the oracle while shooting).
  virtual Rgb unshotIntensityBound(NodeId, const Vec3& /*axis*/, double /*cosHalfAngle*/) const { return Rgb(0.0); }
  /// A node's unshot power, W per channel: how shooters are chosen and when shooting stops. Const, concurrent.
  virtual Rgb unshotPower(NodeId) const { return Rgb(0.0); }
  /// During the host's push, concurrent across leaves: a simulated leaf's samples of this pass (those an
  /// ancestor's reflectShared took excepted; possibly none), reflected and added to both its total
  /// and its unshot light (the samples are then dropped).
  virtual void reflectShot(NodeId /*leaf*/, std::span<const IncidentSample>) {}
  /// A shooter's unshot light has been sent: clear it in the node and its subtree. Concurrent across
  /// disjoint subtrees, after the pass's gather and before its push.
  virtual void shot(NodeId) {}

  // Energy audit: const, concurrent across leaves.
  /// Power a simulated leaf sends through the extension, W per channel; the rest of the light the
  /// extension owns there is absorbed (a lobe's albedo falls toward grazing).
  virtual Rgb reflectedPower(NodeId /*leaf*/) const { return Rgb(0.0); }
  /// Draws an exitant direction of that power from u1, u2 in [0, 1); returns the power the sample
  /// stands for (W per channel; its mean over draws is reflectedPower) and sets dir.
  virtual Rgb sampleExitant(NodeId /*leaf*/, double /*u1*/, double /*u2*/, Vec3& /*dir*/) const { return Rgb(0.0); }

  // Display: const, concurrent.
  /// The extension's radiance leaving a leaf toward unit toEye, W/(m^2 sr), added to the host's B/pi.
  virtual Rgb radiance(NodeId /*leaf*/, const Vec3& /*toEye*/) const { return Rgb(0.0); }
  /// The same at a point whose surface normal is unit `normal` (a curved or smoothly shaded surface
  /// turns away from its leaf's plane): a glossy lobe follows the point's normal, not the leaf's.
  virtual Rgb radiance(NodeId leaf, const Vec3& toEye, const Vec3& /*normal*/) const { return radiance(leaf, toEye); }
  /// The same seen at point `at` (m) of the leaf, with a zero normal meaning the leaf's own: an
  /// extension that keeps a leaf's brightest incident light re-aims it from there, so a highlight is
  /// as sharp as its source, not the leaf.
  virtual Rgb radiance(NodeId leaf, const Vec3& toEye, const Vec3& normal, const Vec3& /*at*/) const {
    return normal == Vec3(0.0) ? radiance(leaf, toEye) : radiance(leaf, toEye, normal);
  }
  /// Directional coefficients a leaf holds (inspection files); 0 for none.
  virtual std::size_t coefficients(NodeId /*leaf*/) const { return 0; }

  // Solution file and statistics: serial.
  /// Version of what save() writes; a file with another version is refused.
  virtual std::uint32_t formatVersion() const { return 1; }
  /// Writes the extension's leaf data for the solution file's tagged section (the host adds name and
  /// version) to a stream: the file takes it without a copy. Called more than once per file (sized,
  /// checksummed, written), so it writes the same bytes each time.
  virtual void save(std::ostream& /*out*/) const {}
  /// Restores what save() wrote (its own options win over configure's), over the leaves of a loaded
  /// solution; throws InputError when damaged.
  virtual void load(std::string_view /*bytes*/, const HostView&) {}
  /// Figures for stats.json's "extension" object.
  virtual std::vector<StatEntry> stats() const { return {}; }
};

}  // namespace hr
