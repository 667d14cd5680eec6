// The Illumination Samples extension's life cycle: options, side tables, split notices, reflection
// at the leaves, the pull above them, convergence and statistics. Queries (sending, oracle, energy,
// display) are in is_queries.cpp, the solution file in is_file.cpp.
#include <glossy/bound.h>
#include <glossy/haar_sum.h>
#include <glossy/illumination_samples.h>
#include <glossy/is_options.h>
#include <glossy/reflection.h>

#include "is_counters.h"

namespace glossy {

namespace {

bool usableNormal(const Vec3& n) { return hr::allFinite(n) && std::abs(glm::length(n) - 1.0) < 1e-6; }

}  // namespace

IlluminationSamples::IlluminationSamples() : basis_(defaultIsBasis()), counters_(std::make_unique<Counters>()) {}
IlluminationSamples::~IlluminationSamples() = default;

std::vector<hr::OptionSpec> IlluminationSamples::options() const { return isOptionSpecs(); }

void IlluminationSamples::configure(const std::vector<hr::OptionValue>& values) { basis_ = parseIsOptions(values); }

bool IlluminationSamples::simulates(const hr::MaterialInfo& m) const {
  return hr::maxComponent(m.specular) > 0.0 && std::isfinite(m.exponent) && m.exponent >= 0.0;
}

void IlluminationSamples::resize(std::size_t elements, std::size_t clusters) {
  elements_.resize(elements);
  clusters_.resize(clusters);
  change_.resize(elements, Rgb(0.0));
}

void IlluminationSamples::attach(const hr::HostView& view) {
  view_ = &view;
  resize(view.elementCount(), view.clusterCount());
}

std::unique_ptr<IlluminationSamples::NodeLight>* IlluminationSamples::slot(hr::NodeId node) {
  auto& table = node.isCluster() ? clusters_ : elements_;
  return node.index() < table.size() ? &table[node.index()] : nullptr;
}

bool IlluminationSamples::isLeaf(std::size_t i) const {
  return view_ && i < view_->elementCount() && view_->info(hr::NodeId{std::uint32_t(i)}).leaf;
}

const IlluminationSamples::NodeLight* IlluminationSamples::light(hr::NodeId node) const {
  const auto& table = node.isCluster() ? clusters_ : elements_;
  return node.index() < table.size() ? table[node.index()].get() : nullptr;
}

void IlluminationSamples::finish(NodeLight& l) const {
  if (const auto* h = std::get_if<HaarDistribution>(&l.dist)) {
    l.power = h->leafIntegral();
    l.peak = h->peak();
  } else {
    l.power = integral(l.dist);
    l.peak = glm::max(Rgb(0.0), boundOver(l.dist, Cap{}));
  }
}

void IlluminationSamples::split(hr::NodeId parent, std::span<const hr::NodeId> children) {
  if (parent.isCluster() || !view_) return;
  std::size_t need = view_->elementCount();
  for (hr::NodeId c : children) need = std::max<std::size_t>(need, c.index() + 1);
  if (need > elements_.size()) resize(need, clusters_.size());
  change_[parent.index()] = Rgb(0.0);  // no longer a leaf: its light is its children's now
  const NodeLight* p = elements_[parent.index()].get();
  for (hr::NodeId c : children) {
    if (c.isCluster()) continue;
    change_[c.index()] = Rgb(0.0);
    if (!p || !(p->area > 0.0)) continue;
    // An exitant intensity scales with area: the child sends its share of the parent's light.
    double ratio = view_->info(c).area / p->area;
    if (!(ratio >= 0.0) || !std::isfinite(ratio)) continue;
    auto l = std::make_unique<NodeLight>(*p);
    std::visit([&](auto& d) { d.scale(ratio); }, l->dist);
    l->area = p->area * ratio;
    finish(*l);
    elements_[c.index()] = std::move(l);
  }
}

void IlluminationSamples::gather(hr::NodeId, std::span<const hr::IncidentSample>) {
  // Illumination Samples reflect at the leaves after the host's push; gather only counts.
  Counters::add(counters_->gatherCalls, 1);
}

void IlluminationSamples::reflect(hr::NodeId leaf, std::span<const hr::IncidentSample> samples) {
  std::uint64_t t0 = threadCpuNs();
  auto* s = slot(leaf);
  if (!s || leaf.isCluster() || !view_) return;
  hr::NodeInfo info = view_->info(leaf);
  Rgb before = *s ? (*s)->power : Rgb(0.0);
  if (info.material >= view_->materialCount() || !usableNormal(info.normal) || !(info.area > 0.0)) {
    s->reset();
  } else {
    hr::MaterialInfo m = view_->material(info.material);
    auto l = std::make_unique<NodeLight>();
    l->normal = info.normal;
    l->area = info.area;
    l->frame = basis_.basis == Basis::Haar ? Frame::around(info.normal) : Frame::world();
    ReflectCounts rc;
    double n = representableExponent(basis_, m.exponent);
    LobeSet lobes = makeLobes(samples, l->frame, info.normal, info.area, m.specular, n, mergeAngle(n), rc);
    if (simulates(m) && !lobes.samples.empty()) {
      l->dist = projectLobes(lobes, basis_, rc);
      finish(*l);
      *s = std::move(l);
    } else {
      s->reset();  // no light on the front of the surface: nothing to hold
    }
    Counters::add(counters_->samplesReceived, rc.received);
    Counters::add(counters_->samplesKept, rc.kept);
    Counters::add(counters_->samplesDropped, rc.dropped);
    Counters::add(counters_->brdfEvaluations, rc.brdfEvaluations);
  }
  change_[leaf.index()] = glm::abs((*s ? (*s)->power : Rgb(0.0)) - before);
  Counters::raise(counters_->samplesPeak, samples.size());
  Counters::add(counters_->reflectCalls, 1);
  Counters::add(counters_->reflectCpuNs, threadCpuNs() - t0);
}

void IlluminationSamples::pull(hr::NodeId node, std::span<const hr::NodeId> children) {
  std::uint64_t t0 = threadCpuNs();
  auto* s = slot(node);
  if (!s || !view_) return;
  std::vector<const NodeLight*> lit;
  for (hr::NodeId c : children)
    if (const NodeLight* l = light(c)) lit.push_back(l);
  if (lit.empty()) {
    s->reset();
    return;
  }
  hr::NodeInfo info = view_->info(node);
  auto l = std::make_unique<NodeLight>();
  l->area = info.area;
  bool planar = !node.isCluster() && info.planar && usableNormal(info.normal);
  l->normal = planar ? info.normal : Vec3(0.0);
  if (basis_.basis == Basis::Haar) {
    // A planar node keeps its own frame; a cluster keeps its children's when they agree.
    Frame target = planar ? Frame::around(info.normal) : lit.front()->frame;
    std::vector<HaarTerm> terms;
    for (const NodeLight* c : lit) {
      terms.push_back({&std::get<HaarDistribution>(c->dist), c->frame});
      if (!planar && !c->frame.same(target)) target = Frame::world();
    }
    HaarSumStats hs;
    l->dist = haarSum(terms, target, basis_.haar, &hs);
    l->frame = target;
    Counters::add(counters_->pullCells, hs.cells);
    Counters::add(counters_->pullClips, hs.clips);
  } else {
    // Fixed bases in the world frame: the sum is exact coefficient by coefficient.
    l->dist = lit.front()->dist;
    for (std::size_t i = 1; i < lit.size(); ++i)
      std::visit([&](auto& d) { d.add(std::get<std::decay_t<decltype(d)>>(lit[i]->dist)); }, l->dist);
    l->frame = Frame::world();
  }
  finish(*l);
  *s = std::move(l);
  Counters::add(counters_->pullCalls, 1);
  Counters::add(counters_->pullCpuNs, threadCpuNs() - t0);
}

double IlluminationSamples::powerChange() const {
  double sum = 0.0;  // index order: the same total for any thread count
  for (const Rgb& c : change_) sum += hr::luminance(c);
  return sum;
}

std::vector<hr::StatEntry> IlluminationSamples::stats() const {
  double distributions = 0, leafDistributions = 0, coefficientsTotal = 0, coefficientsPeak = 0, bytesTotal = 0;
  auto scan = [&](const std::vector<std::unique_ptr<NodeLight>>& table) {
    for (const auto& l : table) {
      bytesTotal += sizeof(l);
      if (!l) continue;
      distributions += 1;
      double c = double(glossy::coefficients(l->dist));
      coefficientsTotal += c;
      coefficientsPeak = std::max(coefficientsPeak, c);
      bytesTotal += double(sizeof(NodeLight) - sizeof(AnyDistribution) + bytes(l->dist));
    }
  };
  scan(elements_);
  scan(clusters_);
  for (std::size_t i = 0; i < elements_.size(); ++i)
    if (elements_[i] && isLeaf(i)) ++leafDistributions;
  bytesTotal += double(change_.capacity() * sizeof(Rgb));
  const Counters& c = *counters_;
  auto v = [](const std::atomic<std::uint64_t>& a) { return double(a.load(std::memory_order_relaxed)); };
  return {
      {"distributions", distributions},
      {"distributions_at_leaves", leafDistributions},
      {"coefficients_total", coefficientsTotal},
      {"coefficients_peak_per_distribution", coefficientsPeak},
      {"bytes", bytesTotal},
      {"samples_received_total", v(c.samplesReceived)},
      {"samples_peak_per_reflect", v(c.samplesPeak)},
      {"samples_merged_away", v(c.samplesReceived) - v(c.samplesDropped) - v(c.samplesKept)},
      {"samples_dropped_no_front_light", v(c.samplesDropped)},
      {"brdf_evaluations", v(c.brdfEvaluations)},
      {"gather_calls", v(c.gatherCalls)},
      {"reflect_leaf_visits", v(c.reflectCalls)},
      {"pull_node_visits", v(c.pullCalls)},
      {"pull_cells_visited", v(c.pullCells)},
      {"pull_cells_clipped", v(c.pullClips)},
      {"reflect_cpu_seconds_summed_over_threads", v(c.reflectCpuNs) * 1e-9},
      {"pull_cpu_seconds_summed_over_threads", v(c.pullCpuNs) * 1e-9},
  };
}

}  // namespace glossy
