// Link refinement: the oracle, the split of a link into its children's links, and the receiver pass.
// Every round evaluates new links and takes its decisions in parallel from the state at the start of
// the round; only the structural step (subdividing elements, which appends nodes) is serial, in link
// order, so the hierarchy and the links are the same whatever the thread count.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <numeric>

#include "counting_sort.h"
#include "solver_state.h"

namespace hr::detail {
namespace {

enum class Action : std::uint8_t { Keep, Drop, SplitSender, SplitReceiver, SplitSelf };

bool canSplit(const SolverState& s, NodeId n) {
  if (n.isCluster()) return !s.h.cluster(n.index()).children.empty();
  const Element& e = s.h.element(n.index());
  return e.level < static_cast<std::uint32_t>(s.opt.maxLevel) && e.area * 0.25 >= s.minArea;
}

/// An intensity I (W/sr) of the sender in the unit links use: itself for a cluster, for an element
/// the radiosity-equivalent pi L = pi I / (A cos), the cosine of the centre direction kept away from
/// zero: a bound for the oracle, not for the transfer (the paper's bounds are not conservative either
/// once exitant light is approximate, §3.1).
double senderUnit(const SolverState& s, const Link& l, double I) {
  if (l.sender.isCluster() || I <= 0.0) return I;
  const Element& e = s.h.element(l.sender.index());
  return kPi * I / (e.area * std::max(glm::dot(e.normal, -Vec3(l.dir)), 0.1));
}

/// The extension's share of a sender's light, bounded over the cone of directions from the sender
/// toward the receiver's bounding sphere (luminance, in the sender's unit: radiosity-equivalent
/// W/m^2 for elements, W/sr for clusters). This is how the spot a glossy reflector throws on a wall
/// gets refined: the intensity toward the wall's centre may miss the highlight. The whole-sphere
/// bound is tried first and the cone only when that would split (the cone costs microseconds).
/// The extension's bound over the cone toward the receiver (or the whole sphere), W/sr (luminance).
double extensionBoundRaw(const SolverState& s, const Link& l, bool wholeSphere = false) {
  const Vec3 axis = -Vec3(l.dir);
  double d = glm::length(s.h.center(l.sender) - s.h.center(l.receiver));
  double sinHalf = d > 0.0 ? (s.h.radius(l.sender) + s.h.radius(l.receiver)) / d : 2.0;
  double cosHalf = wholeSphere || sinHalf >= 1.0 ? -1.0 : std::sqrt(1.0 - sinHalf * sinHalf);
  return luminance(s.extIntensityBound(l.sender, axis, cosHalf));
}

double extensionBound(const SolverState& s, const Link& l, bool wholeSphere) {
  return senderUnit(s, l, extensionBoundRaw(s, l, wholeSphere));
}

/// How much the extension's share varies over the receiver, in the sender's unit: from the largest
/// of the cone's bound and the values toward the receiver's centre and corners to the smallest of
/// those values.
double extensionVariation(const SolverState& s, const Link& l, bool wholeSphere) {
  // The cheap pass: the whole sphere's peak bounds any variation (no direction is looked at).
  if (wholeSphere) return extensionBound(s, l, true);
  const Vec3 from = s.h.center(l.sender);
  auto toward = [&](const Vec3& p) {
    Vec3 d = p - from;
    double len = glm::length(d);
    return len > 0.0 ? luminance(s.extIntensity(l.sender, d / len)) : 0.0;
  };
  double lo = toward(s.h.center(l.receiver)), hi = lo;
  auto visit = [&](const Vec3& p) {
    double v = toward(p);
    lo = std::min(lo, v), hi = std::max(hi, v);
  };
  if (l.receiver.isCluster()) {
    const Aabb& b = s.h.cluster(l.receiver.index()).bounds;
    for (int k = 0; k < 8; ++k) visit(Vec3((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z));
  } else {
    const Element& r = s.h.element(l.receiver.index());
    for (int k = 0; k < r.poly.n; ++k) visit(r.poly.v[k]);
  }
  return senderUnit(s, l, std::max(hi, extensionBoundRaw(s, l))) - senderUnit(s, l, lo);
}

/// The luminance of a link's sender value, computed once per decision: the oracle reads it up to five
/// times, and toward an element receiver a glossy sender's value integrates its distribution over
/// the receiver (Extension::meanIntensity).
class SenderLuminance {
 public:
  SenderLuminance(const SolverState& s, const Link& l) : s_(s), l_(l) {}
  /// A link of the pass's own array: the extension's share is kept in it for the next reads.
  SenderLuminance(const SolverState& s, Link& l) : s_(s), l_(l), keep_(&l) {}
  double operator()() const {
    if (!known_) value_ = luminance(keep_ ? s_.senderValue(*keep_) : s_.senderValue(l_)), known_ = true;
    return value_;
  }

 private:
  const SolverState& s_;
  const Link& l_;
  Link* keep_ = nullptr;
  mutable double value_ = 0.0;
  mutable bool known_ = false;
};

/// The sender's value toward the receiver, or a cluster's peak intensity if that is more, plus the
/// extension's bound when it simulates part of the sender (luminance).
double senderBound(const SolverState& s, const Link& l, bool wholeSphere, const SenderLuminance& value) {
  double S = value();
  if (l.sender.isCluster()) S = std::max(S, s.peak[l.sender.index()]);
  if (s.ext && s.isOwned(l.sender)) S += extensionBound(s, l, wholeSphere);
  return S;
}

/// The oracle, part one: how much of the power the link brings may land in the wrong place on its
/// receiver, W (luminance): the receiver's area times the sender's value times the transfer bound
/// times its relative spread over the receiver. Compared with eps * emitted power.
double placementError(const SolverState& s, const Link& l, bool wholeSphere, const SenderLuminance& value) {
  double uncertainty = std::max<double>(l.spread, l.geom);
  double S = senderBound(s, l, wholeSphere, value) * uncertainty;
  // A directional sender may be much brighter toward part of the receiver than toward another (a
  // highlight landing on a wall): the link gives the whole receiver its value toward the centre, so
  // that variation is misplaced light too, and it is measured both ways: up to the cone's bound, and
  // down to the dimmest of the receiver's corners (a receiver centred on a highlight got the peak
  // over all of it, 26 % too much light in a three-lights spot).
  if (s.ext && s.isOwned(l.sender)) S += extensionVariation(s, l, wholeSphere);
  return catchingArea(s, l) * S * l.bound;
}

/// Part two: how far the power the link moves may be off, W. Two sources:
/// - An inner element sends one mean value for its whole subtree while the receiver sees its parts
///   unequally, so the power may be off by up to the bound times the range of the subtree's
///   radiosity: a plate lit from close above by a small lamp sent the lamp back a third of what its
///   bright centre really sends, while every form factor looked smooth.
/// - A link with a cluster end is a far-field model (intensity over squared distance, transfer.cpp);
///   its error grows like ((r_s + r_r) / d)^2: neighbouring clusters at eps 1 created 72 % of the
///   emitted power. Dark links cost nothing here, so dark neighbourhoods stay coarse.
/// Such errors are lost or created energy, not misplaced light, so they are held to kPowerTolerance
/// of the emitted power even when eps is coarser (decide).
double powerError(const SolverState& s, const Link& l, bool wholeSphere, const SenderLuminance& value) {
  if (l.sender.isCluster() || l.receiver.isCluster()) {
    // With the sender's peak intensity: the model may get the direction wrong (a ceiling seen from a
    // lamp 1 mm below it, but above the ceiling's cluster centre, got nothing from it).
    const double g = double(l.geom), S = senderBound(s, l, wholeSphere, value);
    const double power = catchingArea(s, l) * S * l.bound;
    // The g^2 law holds for compact nodes far apart. Over the nodes' bounding spheres the kernel may
    // exceed the centres' by 1 / (1 - g)^2, and without bound once they overlap: a cluster holding a
    // wall next to the sender and a box 10 m away (the tree splits at the median) has its centre far
    // away, and a floor's link to it gave the wall it meets 0.15 % of the floor's light for its
    // 17 %; shooting lost 17 % of a room's power. So the error is also taken as that excess, capped
    // by all the power the sender sends (an element's area times its radiosity, a cluster's 4 pi
    // times its peak intensity): no link can carry more. Such an error has one sign, though, and
    // many dim shooters each keep one such link: an element's is measured by rays once kept
    // (refineLinks, measureOverlap).
    const double sendable = l.sender.isCluster() ? 4.0 * kPi * S : s.h.area(l.sender) * S;
    const double excess = g < 1.0 ? power * (1.0 / ((1.0 - g) * (1.0 - g)) - 1.0) : sendable;
    return std::max(power * g * g, std::min(excess, sendable));
  }
  if (s.h.element(l.sender.index()).leaf()) return 0.0;
  return s.h.area(l.receiver) * l.bound * double(s.sentMax(l.sender.index()) - s.sentMin(l.sender.index()));
}

/// Part three: light a glossy receiver reflects toward the wrong directions, W (luminance). Every
/// leaf under the receiver reflects this link's light as a lobe about the mirror of the direction
/// to the sender's centre (an Illumination Sample), the same over the leaf's area. When the sender
/// is seen wider than the lobe, or the receiver sees the sender from directions further apart than
/// the lobe (parallax: a mirror 0.3 m from a box), its image is blurred and placed by the centres:
/// the fraction (1 - width / spread) of the reflected power is taken as misplaced, spread = 2 r / d
/// with the larger node's radius, the one decide() splits. The threshold bounds misplaced power
/// as a Lambertian receiver shows it, spread over the hemisphere (projected solid angle pi); a lobe
/// sends it into about pi width^2, so the same power is width^-2 times the radiance error: it is
/// weighed so (on the glossy Cornell box's block, n = 300, the power alone split nothing).
double reflectionError(const SolverState& s, const Link& l, const SenderLuminance& value) {
  if (s.materialReflector.empty() || !s.isOwned(l.receiver)) return 0.0;
  const Reflector r = s.reflector(l.receiver);
  if (r.albedo <= 0.0) return 0.0;
  const double d = glm::length(s.h.center(l.sender) - s.h.center(l.receiver));
  const double reach = 2.0 * std::max(s.h.radius(l.sender), s.h.radius(l.receiver));
  const double share = misplacedReflection(r, reach, d);
  return share > 0.0 ? share * catchingArea(s, l) * value() * double(l.bound) : 0.0;
}

/// A coarse threshold places light coarsely but never loses or makes more than this fraction of the
/// emitted power per link (eps 1 on the Cornell uplight lost 42 % before).
constexpr double kPowerTolerance = 1e-3;

/// The share of that tolerance a partly visible link from an inner element keeps: its receiver's
/// share of the scene's area, at least kPartlyVisibleFloor. Such a link sends its sender's mean
/// radiosity weighted by which children its few rays saw, but within a child the part its rays saw
/// need not be the bright one: a ceiling lit 1 cm above a lamp facing it sent its bright spot, hidden
/// from the walls by the lamp, toward every wall element. Each link held its error to the tolerance,
/// all with the same sign, and the room made 9.7 % of its light at eps 2e-3 (docs/solver.md). Split
/// by area, one sender's links share about one tolerance instead of holding one each: -1.4 %. The
/// floor keeps small receivers from refining without end (1/64, the VISION-like host's, gave -0.17 %
/// for 2.5 times the links).
constexpr double kPartlyVisibleFloor = 1.0 / 16.0;

/// Whether a link's power budget is the partly visible share (the comment above): for links from an
/// inner element to an element.
bool sharesBudget(const SolverState& s, const Link& l) {
  return !l.sender.isCluster() && !l.receiver.isCluster() && !s.h.element(l.sender.index()).leaf();
}

/// A threshold held per area: scaled by the receiver's share of the scene's area, at least `floor`
/// of it (the partly visible budget and the shadow term).
double perArea(const SolverState& s, const Link& l, double threshold, double floor) {
  return threshold * std::max(floor, s.h.area(l.receiver) / std::max(s.sceneArea, 1e-300));
}

double partlyVisibleBudget(const SolverState& s, const Link& l, double powerThreshold) {
  return perArea(s, l, powerThreshold, kPartlyVisibleFloor);
}

/// Whether part of a link is hidden, as its first trace saw it. A decision that reads this has the
/// link traced again if kept (refineLinks), so that its coefficient never comes from the rays that
/// chose to keep it: a budget chosen by those very rays kept the links whose four rays all happened
/// to get through (their light overstated) and split the others, and a closed room of albedo 0.9
/// with two blocks made 8.6 % of its light by shooting and 1.2 % by gathering (mean of seeds 1-4;
/// Shooting.ABrightRoomNeitherMakesNorLosesLight, docs/solver.md).
bool seenPartly(Link& l) {
  l.readVisibility = true;
  return l.seenVisible < kSeenScale;
}

/// Part two's test: whether the power error exceeds the link's budget, reading the visibility only
/// when the answer depends on it (a link that reads it is traced again).
bool powerTooLarge(const SolverState& s, Link& l, double error, double powerThreshold) {
  if (error > powerThreshold) return true;
  return sharesBudget(s, l) && error > partlyVisibleBudget(s, l, powerThreshold) && seenPartly(l);
}

/// The budget a memory cap ranks by.
double powerBudget(const SolverState& s, const Link& l, double powerThreshold) {
  const bool partly = sharesBudget(s, l) && l.seenVisible < kSeenScale;
  return partly ? partlyVisibleBudget(s, l, powerThreshold) : powerThreshold;
}

/// Smallest share of the threshold a shadow boundary across an element receiver gets (shadowError).
constexpr double kShadowFloor = 1.0 / 1024.0;

/// Part four: light a shadow boundary across an element receiver misplaces, W (luminance): up to the
/// smaller of its lit and its hidden part (2 min(V, 1 - V) of the unoccluded power), as the
/// VISION-like host counts it. Held to the threshold scaled by the receiver's share of the scene's
/// area (at least kShadowFloor), as that host holds it: by power alone a floor element of 1/600 of
/// the scene kept a sphere's shadow on floor_gloss blurred at any eps (0.261 of the image, 0.120
/// with this term). V is the first trace's (seenPartly). Leaf senders and emitters only: from every
/// inner sender it took 2-3 times the links (the Cornell box 0.19 -> 0.51 M) for no measured gain.
/// An emitter's inner elements are held to it all the same, because whether a lamp element is still
/// a leaf depends on what other links did first, not on the shadow: gathering reached the lamp from
/// the root cluster's self-link after its links to the walls had split it, so the floor's shadows took
/// no term and stopped at leaves four times as wide as shooting reached from the lamp alone (the
/// Cornell box's direct light: the schemes 4.1 % apart, 0.45 % now; docs/solver.md).
double shadowError(const SolverState& s, Link& l, const SenderLuminance& value, double threshold, double* limit) {
  *limit = threshold;
  if (!s.shadows || l.receiver.isCluster() || l.sender.isCluster() || !(l.bound > 0.0f) ||
      !(s.h.element(l.sender.index()).leaf() || s.emits(l.sender)))
    return 0.0;
  *limit = perArea(s, l, threshold, kShadowFloor);
  const double unoccluded = catchingArea(s, l) * value() * double(l.bound);
  if (unoccluded <= *limit) return 0.0;  // no shadow across it could matter
  l.readVisibility = true;
  const double V = double(l.seenVisible) / kSeenScale;
  return 2.0 * std::min(V, 1.0 - V) * unoccluded;
}

Action decide(const SolverState& s, Link& l, double threshold) {
  const double powerThreshold = std::min(threshold, kPowerTolerance * s.emittedPower);
  if (l.sender == l.receiver) return l.sender.isCluster() ? Action::SplitSelf : Action::Drop;
  bool cs = canSplit(s, l.sender), cr = canSplit(s, l.receiver);
  // Visibility still uncertain after all the rays a link may take (transfer.cpp): split it too.
  const SenderLuminance value(s, l);
  // unoccludedPower (transfer.cpp) with the decision's sender value.
  bool sureOfVisibility =
      l.vsigma == 0.0f || catchingArea(s, l) * value() * double(l.bound) * l.vsigma <= visibilityTolerance(s);
  auto tooLarge = [&](bool wholeSphere) {
    double shadowLimit;
    return powerTooLarge(s, l, powerError(s, l, wholeSphere, value), powerThreshold) ||
           placementError(s, l, wholeSphere, value) > threshold ||
           reflectionError(s, l, value) > threshold || shadowError(s, l, value, threshold, &shadowLimit) > shadowLimit;
  };
  const bool glossy = s.ext && s.isOwned(l.sender);
  if ((cs || cr) && (!sureOfVisibility || (tooLarge(true) && (!glossy || tooLarge(false))))) {
    // The larger node is split.
    bool splitSender = cs && (!cr || s.h.radius(l.sender) > s.h.radius(l.receiver));
    return splitSender ? Action::SplitSender : Action::SplitReceiver;
  }
  // Kept even when every ray was blocked: the link may be partly visible, and its sender may
  // brighten later; dropping such links for good lost 1-2 % of a room's power.
  return l.bound > 0.0f ? Action::Keep : Action::Drop;
}

/// How far over its thresholds a link the oracle splits is (1: at them; the tighter cone bound for a
/// glossy sender): what a memory cap ranks splits by, so the budget's last bytes go where the error
/// is largest.
double urgency(const SolverState& s, const Link& l, double threshold) {
  const double powerThreshold = std::min(threshold, kPowerTolerance * s.emittedPower);
  const SenderLuminance value(s, l);
  double u = std::max({powerError(s, l, false, value) / powerBudget(s, l, powerThreshold), placementError(s, l, false, value) / threshold,
                       reflectionError(s, l, value) / threshold});
  // The shadow term is left out: ranked by it, a budget's last bytes would go to shadow boundaries
  // before links whose error is lost or made energy (SolverState::shadows).
  if (l.vsigma > 0.0f)
    u = std::max(u, catchingArea(s, l) * value() * double(l.bound) * l.vsigma / visibilityTolerance(s));
  return u;
}

/// Hierarchy::subdivideAll makes four children of every leaf it splits.
constexpr std::size_t kChildrenPerLeaf = 4;

/// Number of child links a decision makes, the same before subdivideNamed splits the leaves it names
/// as after: such a leaf has no children yet, and counting its 0 made a memory cap price a leaf's
/// split at 2^32 - 1 links (capRound: never taken) or at minus its links (capReceivers: the glossy
/// Cornell box at 300 MB, a receiver pass estimated at 0.10 M more links made 0.41 M, peak 1.14 x).
std::size_t childCount(const SolverState& s, const Link& l, Action a) {
  auto split = [&](NodeId n) {
    return !n.isCluster() && s.h.element(n.index()).leaf() ? kChildrenPerLeaf : s.h.children(n).size();
  };
  switch (a) {
    case Action::SplitSender: return split(l.sender);
    case Action::SplitReceiver: return split(l.receiver);
    case Action::SplitSelf: {
      // Every ordered pair of children, and the children's self-links (clusters only).
      auto kids = s.h.children(l.sender);
      std::size_t n = kids.size() * kids.size();
      for (NodeId k : kids) n -= k.isCluster() ? 0 : 1;
      return n;
    }
    default: return 0;
  }
}

void writeChildren(const SolverState& s, const Link& l, Action a, Link* out) {
  auto make = [&](NodeId snd, NodeId rcv) {
    *out = Link{};
    out->sender = snd;
    out->receiver = rcv;
    ++out;
  };
  if (a == Action::SplitSelf) {
    auto kids = s.h.children(l.sender);
    for (NodeId x : kids)
      for (NodeId y : kids)
        if (!(x == y) || x.isCluster()) make(x, y);
  } else if (a == Action::SplitSender) {
    for (NodeId k : s.h.children(l.sender)) make(k, l.receiver);
  } else if (a == Action::SplitReceiver) {
    for (NodeId k : s.h.children(l.receiver)) make(l.sender, k);
  }
}

/// The leaf element a decision subdivides, or kNoLeaf.
std::uint32_t splitLeaf(const SolverState& s, const Link& l, Action a) {
  NodeId e = a == Action::SplitSender ? l.sender : a == Action::SplitReceiver ? l.receiver : NodeId{};
  return e.value != kNone && !e.isCluster() && s.h.element(e.index()).leaf() ? e.index() : kNoLeaf;
}

/// Under a memory budget: when a round's decisions would make more links and elements than the cap
/// allows, only the most urgent splits that fit are made, and the others keep their link as it is
/// (evaluated and valid, only coarser). A self-link cannot be kept: it always splits.
void capRound(SolverState& s, LinkArray& links, std::vector<Action>& act, std::size_t keptLinks,
              double threshold) {
  if (!s.cap.active()) return;
  const std::size_t n = links.size(), E = s.h.elements().size();
  std::vector<std::uint8_t> named(E, 0);
  std::size_t all = keptLinks, none = keptLinks, leaves = 0;
  std::vector<std::uint32_t> cand, add, leaf;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t c = childCount(s, links[i], act[i]);
    all += act[i] == Action::Keep ? 1 : c;
    const bool optional = c > 0 && act[i] != Action::SplitSelf;
    none += optional || act[i] == Action::Keep ? 1 : c;
    const std::uint32_t e = splitLeaf(s, links[i], act[i]);
    if (e != kNoLeaf && !named[e]) named[e] = 1, ++leaves;
    if (optional) cand.push_back(std::uint32_t(i)), add.push_back(std::uint32_t(c - 1)), leaf.push_back(e);
  }
  if (s.cap.fits(all, E + kChildrenPerLeaf * leaves)) return;
  std::vector<double> urg(cand.size());
  tbb::parallel_for(std::size_t(0), cand.size(), [&](std::size_t k) { urg[k] = urgency(s, links[cand[k]], threshold); });
  const std::vector<std::uint8_t> take = fitMostUrgent(s.cap, none, E, urg, add, leaf, kChildrenPerLeaf);
  for (std::size_t k = 0; k < cand.size(); ++k)
    if (!take[k]) act[cand[k]] = links[cand[k]].bound > 0.0f ? Action::Keep : Action::Drop, links[cand[k]].capped = true, s.capCut = true;
}

/// Links per block of the parallel bookkeeping: each block is counted, then written, by one task, so
/// every link's position is known before any thread writes and the order is the serial one.
constexpr std::size_t kBlock = 2048;

/// Subdivides the elements the decisions name: found per block in parallel, ordered by their first
/// link (so element ids do not depend on the thread count), split in parallel; then tells the
/// extension about leaves it simulates.
void subdivideNamed(SolverState& s, const LinkArray& links, const std::vector<Action>& act) {
  const std::size_t n = links.size(), blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::vector<std::uint32_t>> named(blocks);
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
    for (std::size_t i = b * kBlock; i != std::min(n, (b + 1) * kBlock); ++i)
      // A receiver split with all its links is named once per run of them, not once per link.
      if (std::uint32_t e = splitLeaf(s, links[i], act[i]); e != kNoLeaf && (named[b].empty() || named[b].back() != e))
        named[b].push_back(e);
  });
  std::vector<std::uint8_t> seen(s.h.elements().size(), 0);
  std::vector<std::uint32_t> fresh;
  for (const auto& block : named)
    for (std::uint32_t e : block)
      if (!seen[e]) seen[e] = 1, fresh.push_back(e);
  if (fresh.empty()) return;
  s.h.subdivideAll(fresh);
  s.growArrays();
  if (!s.ext) return;
  for (std::uint32_t e : fresh)
    if (s.owned[e]) s.ext->split(NodeId{e}, s.h.children(NodeId{e}));
}

/// The capacity a link array of refinement grows to: double, as push_back would; under a memory
/// budget at once the most links the cap allows. Doubling made the cost per link jump whenever the
/// kept links outgrew the array (the Cornell box at 140 MB: a 718k-link array and its copy for 381k
/// links, 113 % of the budget), which no per-link law can predict; an array reserved once is never
/// copied, and its pages cost memory only once written (FillLater).
std::size_t grownCapacity(const SolverState& s, std::size_t n, std::size_t capacity) {
  return std::max(n, s.cap.active() ? s.cap.maxLinks(s.h.elements().size()) : 2 * capacity);
}

/// Resizes a link array, growing its capacity geometrically as push_back would (so the peak is the
/// serial version's), and moving the old links to a new array in parallel: serially, the copies of
/// a growing array and their first touch of fresh pages were most of what refinement could not
/// spread over cores on the Soda Shoppe.
void growTo(const SolverState& s, LinkArray& v, std::size_t n) {
  if (n <= v.capacity()) return v.resize(n);  // nothing is written (FillLater)
  LinkArray w;
  w.reserve(grownCapacity(s, n, v.capacity()));
  w.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, v.size(), kBlock), [&](const auto& r) {
    std::copy(v.begin() + std::ptrdiff_t(r.begin()), v.begin() + std::ptrdiff_t(r.end()), w.begin() + std::ptrdiff_t(r.begin()));
  });
  v.swap(w);
}

/// Replaces `links` by the children of the split ones; appends the kept ones to `kept`. No array is
/// kept beyond what the serial version held (the old `links` is freed once its children are
/// written): a branch that recycled a spare array made it parallel at +42-60 % peak memory.
std::size_t applyDecisions(SolverState& s, LinkArray& links, const std::vector<Action>& act,
                           LinkArray& kept) {
  subdivideNamed(s, links, act);
  const std::size_t n = links.size(), blocks = (n + kBlock - 1) / kBlock;
  auto range = [&](std::size_t b) { return std::pair(b * kBlock, std::min(n, (b + 1) * kBlock)); };
  // Per block: kept links, child links and splits; then each block's first positions.
  std::vector<std::size_t> keepAt(blocks + 1, 0), childAt(blocks + 1, 0), splitsIn(blocks, 0);
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
    s.clkRefine.sawThread();
    auto [lo, hi] = range(b);
    for (std::size_t i = lo; i != hi; ++i) {
      std::size_t c = childCount(s, links[i], act[i]);
      childAt[b + 1] += c;
      splitsIn[b] += c > 0 ? 1 : 0;
      keepAt[b + 1] += act[i] == Action::Keep ? 1 : 0;
    }
  });
  std::partial_sum(keepAt.begin(), keepAt.end(), keepAt.begin());
  std::partial_sum(childAt.begin(), childAt.end(), childAt.begin());
  const std::size_t keptBefore = kept.size();
  growTo(s, kept, keptBefore + keepAt[blocks]);
  LinkArray next(childAt[blocks]);
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
    auto [lo, hi] = range(b);
    Link* keep = kept.data() + keptBefore + keepAt[b];
    Link* child = next.data() + childAt[b];
    for (std::size_t i = lo; i != hi; ++i) {
      if (act[i] == Action::Keep) *keep++ = links[i];
      writeChildren(s, links[i], act[i], child);
      child += childCount(s, links[i], act[i]);
    }
  });
  links = std::move(next);
  return std::accumulate(splitsIn.begin(), splitsIn.end(), std::size_t(0));
}

/// The receiver pass's share of the cap (capRound): receivers to split, most over the threshold
/// first, while all their links moving down still fit.
void capReceivers(SolverState& s, const LinkArray& kept, const std::vector<std::uint32_t>& idx,
                  const std::vector<std::uint32_t>& start, const std::vector<double>& excess,
                  std::vector<std::uint8_t>& splitIt) {
  if (!s.cap.active()) return;
  std::vector<std::uint32_t> cand, add, leaf;
  std::vector<double> urg;
  std::size_t allLinks = kept.size(), leaves = 0;
  for (std::uint32_t g = 0; g < splitIt.size(); ++g) {
    if (!splitIt[g]) continue;
    const Link& first = kept[idx[start[g]]];
    const std::size_t more = (childCount(s, first, Action::SplitReceiver) - 1) * (start[g + 1] - start[g]);
    const std::uint32_t e = splitLeaf(s, first, Action::SplitReceiver);
    cand.push_back(g), add.push_back(std::uint32_t(more)), leaf.push_back(e), urg.push_back(excess[g]);
    allLinks += more, leaves += e != kNoLeaf ? 1 : 0;  // one group per receiver: no leaf twice
  }
  const std::size_t E = s.h.elements().size();
  if (cand.empty() || s.cap.fits(allLinks, E + kChildrenPerLeaf * leaves)) return;
  const std::vector<std::uint8_t> take = fitMostUrgent(s.cap, kept.size(), E, urg, add, leaf, kChildrenPerLeaf);
  for (std::size_t k = 0; k < cand.size(); ++k)
    if (!take[k]) splitIt[cand[k]] = 0, s.capCut = true;
}

/// The receiver pass. The per-link oracle bounds each link's error alone, but a receiver near an
/// edge or corner holds hundreds of links whose small errors share one sign (every one of them
/// averages the form factor over a receiver that straddles a steep gradient), and a leaf's
/// form-factor sum came out 5 % off in a closed cube. So for every element receiver that can still
/// split, the irradiance its element links deliver is also evaluated at its corners and centre; if
/// area * (max - min) exceeds the threshold, the receiver is subdivided and all its links move down
/// to the children (where the per-link oracle sees them again). Only receivers that gained links
/// since kept[from] are examined (all of them on the first pass of an iteration: senders changed).
/// Returns the receivers split.
std::size_t receiverPass(SolverState& s, LinkArray& kept, std::size_t from, LinkArray& out,
                         double threshold) {
  const std::size_t E = s.h.elements().size();
  std::vector<std::uint8_t> check(E, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(from, kept.size(), 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      NodeId n = kept[i].receiver;
      // Several links may mark one receiver: every store writes the same 1.
      if (!n.isCluster() && canSplit(s, n)) std::atomic_ref(check[n.index()]).store(1, std::memory_order_relaxed);
    }
  });
  // The links of the receivers to check, grouped by receiver in link order (a stable sort has one
  // answer whatever the thread count).
  auto key = [&](std::size_t i) {
    NodeId n = kept[i].receiver;
    return !n.isCluster() && check[n.index()] ? std::size_t(n.index()) : E;
  };
  std::vector<std::uint32_t> idx(kept.size());
  const std::vector<std::uint32_t> start =
      countingSort(kept.size(), E, key, [&](std::size_t i, std::uint32_t p) { idx[p] = std::uint32_t(i); });
  const std::size_t groups = start.size() - 1;
  std::vector<double> excess(groups, 0.0);  // area * (max - min) / threshold
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, groups, 16), [&](const auto& r) {
    s.clkRefine.sawThread();
    for (std::size_t g = r.begin(); g != r.end(); ++g) {
      NodeId recv = kept[idx[start[g]]].receiver;
      double e[5] = {0, 0, 0, 0, 0};
      for (std::uint32_t i = start[g]; i < start[g + 1]; ++i) {
        Link& l = kept[idx[i]];
        if (l.sender.isCluster() || l.bound <= 0.0f) continue;
        double S = luminance(s.senderValue(l)) * (double(l.coef) / l.bound);  // times the visible fraction
        for (int k = 0; k < 5; ++k) e[k] += S * l.at[k];
      }
      auto [lo, hi] = std::minmax_element(e, e + 5);
      excess[g] = s.h.area(recv) * (*hi - *lo) / threshold;
    }
  });
  std::vector<std::uint8_t> splitIt(groups, 0);
  for (std::size_t g = 0; g < groups; ++g) splitIt[g] = excess[g] > 1.0 ? 1 : 0;
  capReceivers(s, kept, idx, start, excess, splitIt);
  // Every link of a split receiver becomes a SplitReceiver decision; the rest stay kept, in order.
  std::vector<Action> act(kept.size(), Action::Keep);
  std::size_t count = 0;
  for (std::size_t g = 0; g < groups; ++g) {
    if (!splitIt[g]) continue;
    ++count;
    for (std::uint32_t i = start[g]; i < start[g + 1]; ++i) act[idx[i]] = Action::SplitReceiver;
  }
  if (count == 0) return 0;
  // The grouping is not needed any more: freed before the pass's peak (kept, stay and the children).
  std::vector<std::uint32_t>().swap(idx);
  std::vector<std::uint8_t>().swap(check);
  LinkArray stay;
  applyDecisions(s, kept, act, stay);
  out.swap(kept);
  kept.swap(stay);
  return count;
}

}  // namespace

std::size_t refineLinks(SolverState& s) {
  LinkArray pending = std::move(s.links), kept;
  s.links.clear();
  kept.reserve(s.cap.active() ? grownCapacity(s, pending.size(), 0) : pending.size() + pending.size() / 4);
  std::size_t splitCount = 0, checkedFrom = 0;
  const double threshold = s.opt.eps * s.emittedPower;
  while (!pending.empty()) {
    {
      PhaseTimer t(s.clkVisibility);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pending.size(), 64), [&](const auto& r) {
        s.clkVisibility.sawThread();
        std::uint64_t n = 0, links = 0;
        for (std::size_t i = r.begin(); i != r.end(); ++i)
          if (!pending[i].evaluated) n += std::uint64_t(evaluateLink(s, pending[i])), ++links;
        s.rays += n;
        s.evaluated += links;
      });
    }
    PhaseTimer t(s.clkRefine);
    std::vector<Action> act(pending.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pending.size(), 256), [&](const auto& r) {
      s.clkRefine.sawThread();
      for (std::size_t i = r.begin(); i != r.end(); ++i) act[i] = decide(s, pending[i], threshold), pending[i].capped = false;
    });
    capRound(s, pending, act, kept.size(), threshold);
    splitCount += applyDecisions(s, pending, act, kept);
    if (pending.empty()) {
      splitCount += receiverPass(s, kept, checkedFrom, pending, threshold);
      checkedFrom = kept.size();  // receivers checked now need no second look unless they gain links
    }
  }
  // A kept link whose element sender overlaps its receiver cluster is one the far-field model cannot
  // carry (powerError let it stay because all its sender sends is under the threshold): it carries
  // what rays measure instead. Measured once, after the decisions, so only kept links pay the rays.
  // A kept link whose visibility the oracle read is traced again: its coefficient must not come from
  // the rays that chose to keep it (seenPartly). Once per link: later passes read the first trace.
  {
    PhaseTimer t(s.clkVisibility);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kept.size(), 64), [&](const auto& r) {
      s.clkVisibility.sawThread();
      std::uint64_t n = 0;
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        Link& l = kept[i];
        if (needsMeasure(l)) n += std::uint64_t(measureOverlap(s, l));
        if (l.readVisibility && !l.retraced) n += std::uint64_t(evaluateLink(s, l, true)), l.retraced = true;
      }
      s.rays += n;
    });
  }
  PhaseTimer t(s.clkRefine);
  s.links = std::move(kept);
  s.groupByReceiver(s.links, s.groupStart);
  return splitCount;
}

}  // namespace hr::detail
