// The Illumination Samples extension's life cycle: options, side tables, split notices, reflection
// at the leaves, the pull above them, convergence and statistics. Queries (sending, oracle, energy,
// display) are in is_queries.cpp, the solution file in is_file.cpp.
#include <glossy/basis_rule.h>
#include <glossy/bound.h>
#include <glossy/cell_rules.h>
#include <glossy/haar_sum.h>
#include <glossy/illumination_samples.h>
#include <glossy/is_options.h>
#include <glossy/lobe_level.h>
#include <glossy/reflection.h>

#include "is_counters.h"
#include "lobe_cache.h"

#include <cstdio>

namespace glossy {

namespace {

bool usableNormal(const Vec3& n) { return hr::allFinite(n) && std::abs(glm::length(n) - 1.0) < 1e-6; }

/// The finest level any material may get: the given --dir-max-level, else the lobe rule's finest.
int levelCap(const BasisSpec& b) { return b.haarLevelGiven ? b.haar.maxLevel : std::max(b.haar.minLevel, kLobeLevelFinest); }

}  // namespace

IlluminationSamples::IlluminationSamples()
    : basis_(defaultIsBasis()), counters_(std::make_unique<Counters>()), finestLevel_(levelCap(basis_)) {}
IlluminationSamples::~IlluminationSamples() = default;

std::vector<hr::OptionSpec> IlluminationSamples::options() const { return isOptionSpecs(); }

void IlluminationSamples::configure(const std::vector<hr::OptionValue>& values) {
  basis_ = parseIsOptions(values);
  refineReflections_ = parseReflectionRefine(values);
  senderPoints_ = parseOnOff(values, "sender-extent") ? kSenderPoints : 0;
  exactHighlights_ = parseOnOff(values, "exact-highlights");
  finestLevel_ = levelCap(basis_);
  budgetLevels_ = -1;
  LobeCache::setMaxEntries(LobeCache::kMaxEntries);  // a budget of an earlier solve in this process is not this one's
  basis_.haar.maxLevel = levelFor(0.0);
}

void IlluminationSamples::memoryBudget(std::size_t bytes) {
  // Each thread's lobe memo within 1/64 of the budget: at its default bound (16 MB of shares a
  // thread) it filled late in a 60 MB solve of the glossy Cornell box and took it to 122 %.
  LobeCache::setMaxEntries(bytes / 64 / LobeCache::kBytesPerEntry);
}

void IlluminationSamples::limitDirectionalLevels(int levels) {
  // Only Haar distributions have levels to steer. --basis auto weighed each material's bases at the
  // configured levels (autoChoice): other levels would undo the ground of its choice.
  if (basis_.automatic || basis_.basis != Basis::Haar) return;
  // The budget caps every material's own level (a sharp material's fine cells are what it takes back).
  budgetLevels_ = levels;
  if (view_)
    chooseLevels(*view_);
  else
    basis_.haar.maxLevel = levelFor(0.0);
}

int IlluminationSamples::levelFor(double exponent) const {
  const int lo = basis_.haar.minLevel;
  int level = basis_.haarLevelGiven ? finestLevel_ : std::min(lobeLevel(exponent, lo), finestLevel_);
  if (budgetLevels_ >= 0) level = std::min(level, lo + budgetLevels_);
  return std::max(level, lo);
}

void IlluminationSamples::chooseLevels(const hr::HostView& view) {
  materialLevel_.assign(view.materialCount(), -1);
  int finest = -1, coarsest = -1;
  for (std::uint32_t m = 0; m < view.materialCount(); ++m) {
    hr::MaterialInfo info = view.material(m);
    if (!simulates(info)) continue;
    materialLevel_[m] = levelFor(info.exponent);
    if (materialBasis(m) != Basis::Haar) continue;
    finest = std::max(finest, materialLevel_[m]);
    coarsest = coarsest < 0 ? materialLevel_[m] : std::min(coarsest, materialLevel_[m]);
  }
  basis_.haar.maxLevel = finest >= 0 ? finest : levelFor(0.0);
  pullFloor_ = coarsest >= 0 ? coarsest : basis_.haar.maxLevel;
}

int IlluminationSamples::materialLevel(std::uint32_t id) const {
  return id < materialLevel_.size() && materialLevel_[id] >= 0 ? materialLevel_[id] : basis_.haar.maxLevel;
}

bool IlluminationSamples::simulates(const hr::MaterialInfo& m) const {
  return hr::maxComponent(m.specular) > 0.0 && std::isfinite(m.exponent) && m.exponent >= 0.0;
}

hr::Reflector IlluminationSamples::reflector(const hr::MaterialInfo& m) const {
  if (refineReflections_ == ReflectionRefine::Off || !simulates(m)) return {};
  // A Phong lobe cos^n falls to 1/e at sqrt(2/n) from the mirror direction; the normalised lobe's
  // albedo is at most its specular coefficient (at normal incidence).
  double width = lobeWidth(m.exponent);
  // cell: no finer than the material's Haar cells, which hold the reflected image at their own
  // resolution (the glossy Soda Shoppe's polished brass, n = 10^4: a lobe of 0.8 degrees in cells of
  // 2.8 degrees at level 5). Not the default: finer receivers still place the cells' values more
  // finely on the surface (docs/glossy.md, "The reflection term", has what it costs).
  if (refineReflections_ == ReflectionRefine::Cell && !basis_.automatic && basis_.basis == Basis::Haar)
    width = std::max(width, cellSize(levelFor(m.exponent)));
  return {std::min(1.0, hr::luminance(m.specular)), width};
}

void IlluminationSamples::resize(std::size_t elements, std::size_t clusters) {
  elements_.resize(elements);
  clusters_.resize(clusters);
  unshotElements_.resize(elements);
  unshotClusters_.resize(clusters);
  dirtyElements_.resize(elements, 0);
  dirtyClusters_.resize(clusters, 0);
  change_.resize(elements, Rgb(0.0));
  layers_.resize(elements);
  layerShown_.resize(elements);
  layerFrom_.resize(elements, hr::kNone);
}

void IlluminationSamples::chooseBases(const hr::HostView& view) {
  materialBasis_.assign(view.materialCount(), basis_.basis);
  if (basis_.automatic)
    for (std::uint32_t m = 0; m < view.materialCount(); ++m) {
      hr::MaterialInfo info = view.material(m);
      if (!simulates(info)) continue;
      auto it = std::find_if(autoChoices_.begin(), autoChoices_.end(), [&](const auto& c) { return c.first == info.exponent; });
      if (it == autoChoices_.end()) {
        // Haar is weighed at the level this material would get (the level is a function of the exponent).
        BasisSpec spec = basis_;
        spec.haar.maxLevel = levelFor(info.exponent);
        it = autoChoices_.insert(it, {info.exponent, autoChoice(info.exponent, spec)});
      }
      materialBasis_[m] = it->second.basis;
    }
  chooseLevels(view);
}

Basis IlluminationSamples::materialBasis(std::uint32_t id) const {
  return id < materialBasis_.size() ? materialBasis_[id] : basis_.basis;
}

hr::Rgb IlluminationSamples::NodeLight::totalPower() const {
  Rgb p = power;
  for (const NodeLight& m : more) p += m.power;
  return p;
}

std::size_t IlluminationSamples::NodeLight::totalCoefficients() const {
  std::size_t n = glossy::coefficients(dist);
  for (const NodeLight& m : more) n += glossy::coefficients(m.dist);
  return n;
}

void IlluminationSamples::attach(const hr::HostView& view) {
  view_ = &view;
  chooseBases(view);
  resize(view.elementCount(), view.clusterCount());
  notePeak(held());
}

std::unique_ptr<IlluminationSamples::NodeLight>* IlluminationSamples::slot(Table& elements, Table& clusters,
                                                                           hr::NodeId node) {
  auto& table = node.isCluster() ? clusters : elements;
  return node.index() < table.size() ? &table[node.index()] : nullptr;
}

bool IlluminationSamples::isLeaf(std::size_t i) const {
  return view_ && i < view_->elementCount() && view_->info(hr::NodeId{std::uint32_t(i)}).leaf;
}

const IlluminationSamples::NodeLight* IlluminationSamples::light(hr::NodeId node) const {
  const auto& table = node.isCluster() ? clusters_ : elements_;
  return node.index() < table.size() ? table[node.index()].get() : nullptr;
}

const IlluminationSamples::NodeLight* IlluminationSamples::unshotLight(hr::NodeId node) const {
  const auto& table = node.isCluster() ? unshotClusters_ : unshotElements_;
  return node.index() < table.size() ? table[node.index()].get() : nullptr;
}

void IlluminationSamples::touch(hr::NodeId node) {
  auto& dirty = node.isCluster() ? dirtyClusters_ : dirtyElements_;
  if (node.index() < dirty.size()) dirty[node.index()] = 1;
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
  for (Table* table : {&elements_, &unshotElements_}) {
    const NodeLight* p = (*table)[parent.index()].get();
    for (hr::NodeId c : children) {
      if (c.isCluster()) continue;
      change_[c.index()] = Rgb(0.0);
      touch(c);
      if (!p || !(p->area > 0.0)) continue;
      // An exitant intensity scales with area: the child sends its share of the parent's light.
      double ratio = view_->info(c).area / p->area;
      if (!(ratio >= 0.0) || !std::isfinite(ratio)) continue;
      auto l = std::make_unique<NodeLight>(*p);
      auto scaled = [&](NodeLight& part) {
        std::visit([&](auto& d) { d.scale(ratio); }, part.dist);
        part.area = p->area * ratio;
        finish(part);
      };
      scaled(*l);
      for (NodeLight& m : l->more) scaled(m);
      auto shown = l->shown;
      // A child leaf of a curved surface (a display cell, or a split sphere leaf) faces elsewhere:
      // its light is re-projected into its own frame under its own horizon, as a leaf is reflected
      // and as a solution file restores it (a copy in the parent's frame came back turned).
      const hr::NodeInfo ci = view_->info(c);
      if (ci.leaf && usableNormal(ci.normal) && l->normal != Vec3(0.0) && glm::dot(l->normal, ci.normal) < 1.0 - 1e-12) {
        const NodeLight* one[1] = {l.get()};
        l = sum(c, one);
        l->shown = std::move(shown);
      }
      (*table)[c.index()] = std::move(l);
    }
  }
}

void IlluminationSamples::gather(hr::NodeId, std::span<const hr::IncidentSample>) {
  // Illumination Samples reflect at the leaves after the host's push; gather only counts.
  Counters::add(counters_->gatherCalls, 1);
}

std::size_t IlluminationSamples::reflectShared(hr::NodeId element, std::span<hr::IncidentSample> samples) {
  if (element.isCluster() || !view_ || element.index() >= layers_.size()) return samples.size();
  const std::uint32_t e = element.index(), from = layerFrom_[e];
  const hr::NodeInfo info = view_->info(element);
  auto children = view_->children(element);
  // Layers hold Haar cell sums in the element's plane: every leaf below must lie in that plane.
  bool fits = info.planar && !info.leaf && info.material < view_->materialCount() && usableNormal(info.normal) &&
              materialBasis(info.material) == Basis::Haar && simulates(view_->material(info.material));
  for (hr::NodeId c : children) fits = fits && !c.isCluster() && view_->info(c).normal == info.normal;
  if (!fits) {
    // Declined: the host carries these samples down; what the ancestors took still reaches the leaves.
    if (from != hr::kNone) throw std::logic_error("reflectShared: a shared layer above an element it cannot take");
    for (hr::NodeId c : children)
      if (!c.isCluster() && c.index() < layerFrom_.size()) layerFrom_[c.index()] = hr::kNone;
    return samples.size();
  }
  const hr::MaterialInfo m = view_->material(info.material);
  // Parallax: a sample is the same for every leaf below only while the subtree, seen from its sender,
  // spans less than what the leaf's distribution resolves (the lobe, or the Haar cell if wider); a
  // nearer sender is left to the host, which re-aims it from each leaf (the glossy Cornell box's tall
  // block mirrored the short block 0.3 m away smeared upward from one direction per 30 cm element).
  const double resolved = std::max(lobeWidth(m.exponent), cellSize(materialLevel(info.material)));
  const double half = 0.5 * info.bounds.diagonal();
  auto aimed = std::stable_partition(samples.begin(), samples.end(), [&](const hr::IncidentSample& s) {
    return s.distance > 0.0 && half > resolved * s.distance;
  });
  const std::span<const hr::IncidentSample> taken(aimed, samples.end());
  ReflectCounts rc;
  // Per unit area: each leaf scales the sums by its own area, as its own samples' lobes are.
  LobeSet lobes = makeLobes(taken, Frame::around(info.normal), info.normal, 1.0, m.specular, m.exponent,
                            mergeAngle(m.exponent), rc, senderPoints_, resolved);
  std::uint32_t reach = from;
  if (!lobes.samples.empty()) {
    const HaarCellSums* above = from != hr::kNone ? layers_[from].get() : nullptr;
    layers_[e] = std::make_unique<HaarCellSums>(integrateLobes(lobes, materialLevel(info.material), rc, above));
    // The display's shown light of the layer, as a leaf keeps its own (shown_light.h).
    if (exactHighlights_)
      layerShown_[e] = joinShown(from != hr::kNone ? layerShown_[from] : nullptr,
                                 keepShown(taken, info.center, info.normal, m.specular, m.exponent,
                                           materialLevel(info.material), senderPoints_));
    reach = e;
  }
  for (hr::NodeId c : children) layerFrom_[c.index()] = reach;
  counters_->add(rc);
  Counters::add(counters_->sharedLayers, 1);
  return std::size_t(aimed - samples.begin());
}

std::unique_ptr<IlluminationSamples::NodeLight> IlluminationSamples::reflected(hr::NodeId leaf,
                                                                             std::span<const hr::IncidentSample> samples,
                                                                             bool shared) {
  hr::NodeInfo info = view_->info(leaf);
  if (info.material >= view_->materialCount() || !usableNormal(info.normal) || !(info.area > 0.0)) return nullptr;
  // What the ancestors reflected for every leaf below them (reflectShared), per unit area.
  const std::uint32_t from = shared && leaf.index() < layerFrom_.size() ? layerFrom_[leaf.index()] : hr::kNone;
  const HaarCellSums* base = from != hr::kNone ? layers_[from].get() : nullptr;
  hr::MaterialInfo m = view_->material(info.material);
  auto l = std::make_unique<NodeLight>();
  l->normal = info.normal;
  l->area = info.area;
  BasisSpec spec = basis_.with(materialBasis(info.material));
  spec.haar.maxLevel = materialLevel(info.material);
  l->frame = spec.basis == Basis::Haar ? Frame::around(info.normal) : Frame::world();
  ReflectCounts rc;
  double n = representableExponent(spec, m.exponent);
  LobeSet lobes = makeLobes(samples, l->frame, info.normal, info.area, m.specular, n, mergeAngle(n), rc, senderPoints_,
                            spec.basis == Basis::Haar ? cellSize(spec.haar.maxLevel) : 0.0);
  std::unique_ptr<NodeLight> out;
  if (simulates(m) && (!lobes.samples.empty() || base)) {
    l->dist = projectLobes(lobes, spec, rc, base, info.area);
    finish(*l);
    // The brightest samples stay for the display (shown_light.h); Haar cells are what they sharpen.
    if (spec.basis == Basis::Haar && exactHighlights_)
      l->shown = joinShown(from != hr::kNone ? layerShown_[from] : nullptr,
                           keepShown(samples, info.center, info.normal, m.specular, n, spec.haar.maxLevel, senderPoints_));
    out = std::move(l);
  }
  counters_->add(rc);
  return out;
}

void IlluminationSamples::reflect(hr::NodeId leaf, std::span<const hr::IncidentSample> samples) {
  std::uint64_t t0 = threadCpuNs();
  auto* s = slot(leaf);
  if (!s || leaf.isCluster() || !view_) return;
  Rgb before = *s ? (*s)->power : Rgb(0.0);
  *s = reflected(leaf, samples, true);  // null: no light on the front of the surface, nothing to hold
  touch(leaf);
  change_[leaf.index()] = glm::abs((*s ? (*s)->power : Rgb(0.0)) - before);
  Counters::raise(counters_->samplesPeak, samples.size());
  Counters::add(counters_->reflectCalls, 1);
  Counters::add(counters_->reflectCpuNs, threadCpuNs() - t0);
}

void IlluminationSamples::reflectShot(hr::NodeId leaf, std::span<const hr::IncidentSample> samples) {
  std::uint64_t t0 = threadCpuNs();
  auto* s = slot(leaf);
  auto* u = slot(unshotElements_, unshotClusters_, leaf);
  if (!s || !u || leaf.isCluster() || !view_) return;
  // With what an ancestor reflected for every leaf below it this pass (reflectShared), if it did.
  if (std::unique_ptr<NodeLight> add = reflected(leaf, samples, true)) {
    // The pass's reflection joins the total and the unshot light; the samples are then dropped.
    for (auto* target : {s, u}) {
      if (!*target) {
        *target = std::make_unique<NodeLight>(*add);
        if (target == u) (*target)->shown.reset();  // only the total is displayed
        continue;
      }
      const NodeLight* parts[2] = {target->get(), add.get()};
      // A sum keeps no shown light of its own: the leaf's passes' brightest samples together.
      auto shown = target == s ? joinShown((*target)->shown, add->shown) : nullptr;
      *target = sum(leaf, parts);
      (*target)->shown = std::move(shown);
    }
    touch(leaf);
  }
  Counters::raise(counters_->samplesPeak, samples.size());
  Counters::add(counters_->reflectCalls, 1);
  Counters::add(counters_->reflectCpuNs, threadCpuNs() - t0);
}

void IlluminationSamples::shot(hr::NodeId node) {
  shooting_.store(true, std::memory_order_relaxed);
  auto* u = slot(unshotElements_, unshotClusters_, node);
  if (!u || !view_) return;
  u->reset();
  touch(node);
  for (hr::NodeId c : view_->children(node)) shot(c);
}

std::unique_ptr<IlluminationSamples::NodeLight> IlluminationSamples::sum(hr::NodeId node,
                                                                       std::span<const NodeLight* const> parts) const {
  // Grouped by basis (the variant's index is the Basis), parts of parts included.
  std::vector<const NodeLight*> byBasis[3];
  for (const NodeLight* p : parts) {
    if (!p) continue;
    byBasis[p->dist.index()].push_back(p);
    for (const NodeLight& m : p->more) byBasis[m.dist.index()].push_back(&m);
  }
  std::unique_ptr<NodeLight> out;
  for (std::size_t b = 0; b < 3; ++b) {
    if (byBasis[b].empty()) continue;
    NodeLight one = sumOneBasis(node, Basis(b), byBasis[b]);
    if (!out)
      out = std::make_unique<NodeLight>(std::move(one));
    else
      out->more.push_back(std::move(one));
  }
  return out;
}

IlluminationSamples::NodeLight IlluminationSamples::sumOneBasis(hr::NodeId node, Basis b,
                                                                std::span<const NodeLight* const> lit) const {
  hr::NodeInfo info = view_->info(node);
  NodeLight out;
  NodeLight* l = &out;
  l->area = info.area;
  // A leaf reflects about its one normal, curved or not (reflected()), so its summed light keeps that
  // horizon and frame: a curved leaf's sum without them showed no glossy radiance at all (radiance()
  // needs the horizon's cosine), e.g. a shiny sphere on the VISION-like host after its second pass.
  bool planar = !node.isCluster() && (info.planar || info.leaf) && usableNormal(info.normal);
  l->normal = planar ? info.normal : Vec3(0.0);
  if (b == Basis::Haar) {
    // A planar node keeps its own frame; a cluster keeps its children's when they agree.
    Frame target = planar ? Frame::around(info.normal) : lit.front()->frame;
    std::vector<HaarTerm> terms;
    for (const NodeLight* c : lit) {
      terms.push_back({&std::get<HaarDistribution>(c->dist), c->frame});
      if (!planar && !c->frame.same(target)) target = Frame::world();
    }
    // As fine as the finest part (a sharp material's lobes are not coarsened on the way up), never
    // coarser than the coarsest material's level (a re-projection into another frame may need it).
    int depth = 0;
    for (const HaarTerm& t : terms) depth = std::max(depth, t.tree->depth());
    HaarOptions o = basis_.haar;
    o.maxLevel = std::clamp(depth, std::min(pullFloor_, o.maxLevel), o.maxLevel);
    HaarSumStats hs;
    l->dist = haarSum(terms, target, o, &hs, planar);
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
  return out;
}

void IlluminationSamples::pull(hr::NodeId node, std::span<const hr::NodeId> children) {
  std::uint64_t t0 = threadCpuNs();
  // Its subtree has been reflected: the layer it shared with its leaves is done with.
  if (!node.isCluster() && node.index() < layers_.size()) layers_[node.index()].reset(), layerShown_[node.index()].reset();
  auto* s = slot(node);
  auto* u = slot(unshotElements_, unshotClusters_, node);
  if (!s || !u || !view_) return;
  // A node whose children did not change since its last pull keeps its light (a shooting pass
  // reaches few leaves); each child's mark is read by this, its only parent.
  bool changed = false;
  for (hr::NodeId c : children) {
    auto& dirty = c.isCluster() ? dirtyClusters_ : dirtyElements_;
    if (c.index() < dirty.size() && dirty[c.index()]) changed = true, dirty[c.index()] = 0;
  }
  if (!changed) return;
  std::vector<const NodeLight*> total, unshot;
  for (hr::NodeId c : children) total.push_back(light(c)), unshot.push_back(unshotLight(c));
  // While shooting a host reads only the unshot light above the leaves (hr/extension.h, pull): the
  // total there would be a second Haar sum per node and pass that nothing reads (on the glossy
  // sphere, half of a shooting solve's pull).
  if (shooting_.load(std::memory_order_relaxed))
    s->reset();
  else
    *s = sum(node, total);
  *u = sum(node, unshot);
  touch(node);
  Counters::add(counters_->pullCalls, 1);
  Counters::add(counters_->pullCpuNs, threadCpuNs() - t0);
}

double IlluminationSamples::powerChange() const {
  double sum = 0.0;  // index order: the same total for any thread count
  for (const Rgb& c : change_) sum += hr::luminance(c);
  return sum;
}

hr::Rgb IlluminationSamples::totalPower(hr::NodeId node) const {
  const NodeLight* l = light(node);
  return l ? l->totalPower() : Rgb(0.0);
}

hr::Rgb IlluminationSamples::unshotPower(hr::NodeId node) const {
  const NodeLight* l = unshotLight(node);
  return l ? l->totalPower() : Rgb(0.0);
}

double IlluminationSamples::held() const {
  double n = 0.0;
  for (const Table* t : {&elements_, &clusters_, &unshotElements_, &unshotClusters_})
    for (const auto& l : *t)
      if (l) n += double(l->totalCoefficients());
  return n;
}

void IlluminationSamples::notePeak(double now) { peakHeld_ = std::max(peakHeld_, now); }

std::size_t IlluminationSamples::heldBytes() const {
  // The statistics' figure, so the two never disagree; once per pass, like the statistics' scan.
  for (const hr::StatEntry& e : stats())
    if (e.name == "bytes") return std::size_t(e.value);
  return 0;
}

std::vector<hr::StatEntry> IlluminationSamples::stats() const {
  double distributions = 0, leafDistributions = 0, coefficientsTotal = 0, coefficientsPeak = 0, bytesTotal = 0;
  double mixedNodes = 0;  // parts beyond the first in nodes mixing bases
  double shownLights = 0, shownSamples = 0, shownPieces = 0;  // the display's shown light (shown_light.h)
  auto scan = [&](const std::vector<std::unique_ptr<NodeLight>>& table) {
    for (const auto& l : table) {
      bytesTotal += sizeof(l);
      if (!l) continue;
      distributions += 1;
      double c = double(l->totalCoefficients());
      coefficientsTotal += c;
      coefficientsPeak = std::max(coefficientsPeak, c);
      bytesTotal += double(sizeof(NodeLight) - sizeof(AnyDistribution) + bytes(l->dist));
      if (l->shown) {  // counted at every node that shares it: a bound
        shownLights += 1, shownSamples += double(l->shown->samples.size());
        shownPieces += double(l->shown->deposited.size());
        const double held = double(l->shown->samples.capacity() + l->shown->deposited.capacity());
        bytesTotal += double(sizeof(ShownLight)) + held * double(sizeof(ShownLight::Sample));
      }
      for (const NodeLight& m : l->more) {
        bytesTotal += double(sizeof(NodeLight) - sizeof(AnyDistribution) + bytes(m.dist));
        mixedNodes += 1;
      }
    }
  };
  scan(elements_);
  scan(clusters_);
  const double total = coefficientsTotal, totalDistributions = distributions;
  scan(unshotElements_);
  scan(unshotClusters_);
  for (std::size_t i = 0; i < elements_.size(); ++i)
    if (elements_[i] && isLeaf(i)) ++leafDistributions;
  bytesTotal += double(change_.capacity() * sizeof(Rgb));
  const Counters& c = *counters_;
  auto v = [](const std::atomic<std::uint64_t>& a) { return double(a.load(std::memory_order_relaxed)); };
  std::vector<hr::StatEntry> out = {
      {"distributions", totalDistributions},
      {"distributions_at_leaves", leafDistributions},
      {"coefficients_total", total},
      {"distributions_unshot", distributions - totalDistributions},
      {"coefficients_unshot", coefficientsTotal - total},
      {"coefficients_held_peak", std::max(peakHeld_, coefficientsTotal)},
      {"coefficients_peak_per_distribution", coefficientsPeak},
      {"bytes", bytesTotal},
      {"samples_received_total", v(c.samplesReceived)},
      {"samples_peak_per_reflect", v(c.samplesPeak)},
      {"samples_merged_away", v(c.samplesReceived) + v(c.spreadLobes) - v(c.samplesDropped) - v(c.samplesKept)},
      {"samples_spread_over_their_sender", v(c.samplesSpread)},
      {"lobes_added_by_spreading", v(c.spreadLobes)},
      {"samples_dropped_no_front_light", v(c.samplesDropped)},
      {"brdf_evaluations", v(c.brdfEvaluations)},
      {"lobes_integrated", v(c.lobesIntegrated)},
      {"lobes_from_memo", v(c.lobesFromMemo)},
      {"reflect_shared_layers", v(c.sharedLayers)},
      {"gather_calls", v(c.gatherCalls)},
      {"reflect_leaf_visits", v(c.reflectCalls)},
      {"pull_node_visits", v(c.pullCalls)},
      {"pull_cells_visited", v(c.pullCells)},
      {"pull_cells_clipped", v(c.pullClips)},
      {"reflect_cpu_seconds_summed_over_threads", v(c.reflectCpuNs) * 1e-9},
      {"pull_cpu_seconds_summed_over_threads", v(c.pullCpuNs) * 1e-9},
      {"distribution_parts_in_other_bases", mixedNodes},
      {"leaves_with_shown_light", shownLights},
      {"shown_samples", shownSamples},
      {"shown_pieces", shownPieces},
      {"dir_max_level_used", double(basis_.haar.maxLevel)},  // the finest of the materials' levels (budget: held lower)
  };
  // Which basis each glossy material's leaves hold (the choice --basis auto made, or the one given).
  if (view_)
    for (std::uint32_t m = 0; m < view_->materialCount(); ++m) {
      hr::MaterialInfo info = view_->material(m);
      if (!simulates(info)) continue;
      const std::string name = view_->materialName(m);
      std::string key = "basis_material_" + std::to_string(m) + (name.empty() ? "" : "_" + name);
      char text[256];
      std::snprintf(text, sizeof text, "%s (given, exponent %g)", basisName(materialBasis(m)), info.exponent);
      for (const auto& [exponent, choice] : autoChoices_)
        if (basis_.automatic && exponent == info.exponent && choice.basis == materialBasis(m))
          std::snprintf(text, sizeof text, "%s (auto, exponent %g; lobe l2 error haar %.3f, tetra %.3f, sh %.3f; "
                        "weighed by solve cost %.3f, %.3f, %.3f)",
                        basisName(choice.basis), exponent, choice.l2RelError[0], choice.l2RelError[1], choice.l2RelError[2],
                        choice.merit[0], choice.merit[1], choice.merit[2]);
      out.push_back({key, std::string(text)});
      // The finest Haar level its leaves are refined to (lobe_level.h, or --dir-max-level, or the budget's).
      if (materialBasis(m) == Basis::Haar)
        out.push_back({"dir_max_level_material_" + std::to_string(m) + (name.empty() ? "" : "_" + name), double(materialLevel(m))});
    }
  return out;
}

}  // namespace glossy
