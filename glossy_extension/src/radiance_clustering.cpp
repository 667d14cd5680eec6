// Radiance Clustering's immediate push (radiance_clustering.h): one descent per sample from its
// receiver to the simulated leaves below, a reflection and projection per sample and leaf, summed into
// the leaf's new distribution; the swap when the host's push reaches the leaf. The host calls gather
// top-down (a receiver after every receiver above it, concurrent only across disjoint subtrees), so a
// leaf's new distribution is written by one thread at a time and always in the same order.
#include <glossy/radiance_clustering.h>

#include "is_counters.h"

namespace glossy {

struct RadianceClustering::RcCounters {
  std::atomic<std::uint64_t> descents{0}, nodeVisits{0}, leafProjections{0};
  std::atomic<std::int64_t> gatheredCoefficients{0};  // net coefficients added to new distributions this pass
};

RadianceClustering::RadianceClustering() : rc_(std::make_unique<RcCounters>()) {}
RadianceClustering::~RadianceClustering() = default;

std::vector<hr::OptionSpec> RadianceClustering::options() const {
  std::vector<hr::OptionSpec> specs = IlluminationSamples::options();
  specs.push_back({"rc-add", "exact (default) or recut: how a reflected sample's projection joins a leaf's new "
                             "distribution: added exactly on the union of the two trees, as the paper's RC adds "
                             "functions, or the sum re-projected with the relative refiner (docs/results.md)"});
  return specs;
}

void RadianceClustering::configure(const std::vector<hr::OptionValue>& values) {
  std::vector<hr::OptionValue> rest;
  const hr::OptionValue* add = nullptr;
  for (const hr::OptionValue& v : values) {
    if (v.name != "rc-add") {
      rest.push_back(v);
      continue;
    }
    if (add) throw hr::InputError("--rc-add: given twice");
    add = &v;
  }
  if (add && add->value != "exact" && add->value != "recut")
    throw hr::InputError("--rc-add: must be exact or recut, got '" + add->value + "'");
  recut_ = add && add->value == "recut";
  IlluminationSamples::configure(rest);
}

bool RadianceClustering::addExactly(NodeLight& target, const NodeLight& add) const {
  if (!target.more.empty() || !add.more.empty() || target.dist.index() != add.dist.index()) return false;
  if (std::holds_alternative<HaarDistribution>(target.dist) && !target.frame.same(add.frame)) return false;
  std::visit([&](auto& d) { d.add(std::get<std::decay_t<decltype(d)>>(add.dist)); }, target.dist);
  finish(target);
  return true;
}

void RadianceClustering::resize(std::size_t elements, std::size_t clusters) {
  IlluminationSamples::resize(elements, clusters);
  fresh_.resize(elements);
}

double RadianceClustering::held() const {
  double n = IlluminationSamples::held();
  for (const auto& l : fresh_)
    if (l) n += double(glossy::coefficients(l->dist));
  return n;
}

std::uint8_t RadianceClustering::markSimulated(hr::NodeId node) {
  std::uint8_t below = 0;
  auto kids = view_->children(node);
  if (kids.empty()) {
    hr::NodeInfo info = view_->info(node);
    below = info.material < view_->materialCount() && simulates(view_->material(info.material)) ? 1 : 0;
  } else {
    for (hr::NodeId k : kids) below |= markSimulated(k);
  }
  simulated_[node.isCluster() ? view_->elementCount() + node.index() : node.index()] = below;
  return below;
}

bool RadianceClustering::simulatedBelow(hr::NodeId node) const {
  std::size_t k = node.isCluster() ? view_->elementCount() + node.index() : node.index();
  return k < simulated_.size() && simulated_[k] != 0;
}

void RadianceClustering::attach(const hr::HostView& view) {
  // The peak of what is held comes when a pass's gather ends: every leaf's old light and its new one
  // at once. That pass ended before this attach (or before stats(), for the last one).
  notePeak(heldAtAttach_ + double(rc_->gatheredCoefficients.exchange(0, std::memory_order_relaxed)));
  IlluminationSamples::attach(view);
  simulated_.assign(view.elementCount() + view.clusterCount(), 0);
  markSimulated(view.root());
  heldAtAttach_ = held();
}

void RadianceClustering::gather(hr::NodeId receiver, std::span<const hr::IncidentSample> samples) {
  Counters::add(counters_->gatherCalls, 1);
  if (!view_) return;
  for (const hr::IncidentSample& s : samples) {
    if (!(hr::maxComponent(s.irradiance) > 0.0)) continue;  // no light: nothing to push (the host's push skips these too)
    Counters::add(rc_->descents, 1);
    push(receiver, s, !receiver.isCluster());
  }
}

void RadianceClustering::push(hr::NodeId node, hr::IncidentSample sample, bool planar) {
  if (!simulatedBelow(node)) return;
  Counters::add(rc_->nodeVisits, 1);
  auto kids = view_->children(node);
  if (!node.isCluster() && !planar) {
    // Entering a patch from a cluster: E_perp on its plane, once for the whole (coplanar) subtree.
    double c = glm::dot(view_->info(node).normal, sample.toSender);
    if (!(c > 0.0)) return;
    sample.irradiance *= c;
    planar = true;
  }
  if (!kids.empty()) {
    // Each child sees a near sender from its own centre, as Illumination Samples' leaves do (the
    // host re-aims what it carries down): the baseline gets the same parallax as the method.
    const hr::Vec3 from = view_->info(node).center;
    for (hr::NodeId k : kids) {
      hr::IncidentSample mine = sample;
      hr::aimFrom(mine, from, view_->info(k).center);
      push(k, mine, planar);
    }
    return;
  }
  std::uint64_t t0 = threadCpuNs();
  // A leaf: this one sample reflected and projected alone, then summed into the new distribution.
  if (std::unique_ptr<NodeLight> add = reflected(node, {&sample, 1})) {
    Counters::add(rc_->leafProjections, 1);
    auto& target = fresh_[node.index()];
    std::int64_t before = target ? std::int64_t(glossy::coefficients(target->dist)) : 0;
    if (!target) {
      target = std::move(add);
    } else {
      // The display's shown light gathers sample by sample, as Illumination Samples keep it at once.
      auto shown = joinShown(target->shown, add->shown);
      if (recut_ || !addExactly(*target, *add)) {
        const NodeLight* parts[2] = {target.get(), add.get()};
        target = sum(node, parts);
      }
      target->shown = std::move(shown);
    }
    Counters::add(counters_->reflectCpuNs, threadCpuNs() - t0);
    rc_->gatheredCoefficients.fetch_add(std::int64_t(glossy::coefficients(target->dist)) - before,
                                        std::memory_order_relaxed);
  }
}

void RadianceClustering::reflect(hr::NodeId leaf, std::span<const hr::IncidentSample>) {
  // The swap: what this pass gathered becomes the leaf's light (Jacobi, as Illumination Samples).
  auto* s = slot(leaf);
  if (!s || leaf.isCluster() || leaf.index() >= fresh_.size()) return;
  Rgb before = *s ? (*s)->power : Rgb(0.0);
  *s = std::move(fresh_[leaf.index()]);
  touch(leaf);
  change_[leaf.index()] = glm::abs((*s ? (*s)->power : Rgb(0.0)) - before);
  Counters::add(counters_->reflectCalls, 1);
}

std::vector<hr::StatEntry> RadianceClustering::stats() const {
  std::vector<hr::StatEntry> out = IlluminationSamples::stats();
  auto v = [](const auto& a) { return double(a.load(std::memory_order_relaxed)); };
  for (auto& e : out)
    if (e.name == "coefficients_held_peak") e.value = std::max(e.value, heldAtAttach_ + v(rc_->gatheredCoefficients));
  out.push_back({"rc_sample_descents", v(rc_->descents)});
  out.push_back({"rc_descent_node_visits", v(rc_->nodeVisits)});
  out.push_back({"rc_leaf_projections", v(rc_->leafProjections)});
  return out;
}

}  // namespace glossy
