// The two shortcuts of reflection that must not change a bit of its result: the per-thread memo of a
// lobe's cell integrals (a projection from the memo equals one integrated afresh, on another thread
// with an empty memo) and the grid that finds a sample's merge group (the same groups as comparing each
// sample with every group before it, the rule makeLobes states).
#include <glossy/brdf.h>
#include <glossy/is_options.h>
#include <glossy/reflection.h>
#include <gtest/gtest.h>

#include <random>
#include <sstream>
#include <thread>

#include "fake_host.h"
#include "lobe_cache.h"

namespace {

using glossy::Rgb;
using glossy::Vec3;
using glossy::kPi;

std::vector<hr::IncidentSample> spreadSamples(std::uint64_t seed, int count, const Vec3& centre, double spread) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<hr::IncidentSample> out;
  for (int k = 0; k < count; ++k) {
    Vec3 d = testhost::around(centre, spread * std::sqrt(u(g)), 2.0 * kPi * u(g));
    out.push_back(testhost::sample(d, std::pow(10.0, -3.0 * u(g)) * Rgb(0.5 + u(g), 0.5 + u(g), 0.5 + u(g))));
  }
  return out;
}

std::string bytesOf(const glossy::AnyDistribution& d) {
  std::ostringstream s;
  std::get<glossy::HaarDistribution>(d).serialize(s);
  return s.str();
}

/// Projects the samples as one leaf would (frame of +z, exponent n, level 4), returning the
/// distribution's bytes and the memo counts.
std::string project(const std::vector<hr::IncidentSample>& samples, double n, glossy::ReflectCounts& rc) {
  glossy::BasisSpec b = glossy::defaultIsBasis();
  b.haar.maxLevel = 4;
  glossy::LobeSet lobes =
      glossy::makeLobes(samples, glossy::Frame::world(), Vec3(0, 0, 1), 0.25, Rgb(0.5, 0.4, 0.3), n, 0.0, rc);
  return bytesOf(glossy::projectLobes(lobes, b, rc));
}

TEST(LobeMemo, ReplayedLobesGiveTheBitsOfAFreshIntegration) {
  // Lobes over the whole hemisphere, broad to sharp (the Soda Shoppe's exponents).
  for (double n : {40.0, 406.163, 2220.22, 1e4}) {
    auto samples = spreadSamples(7, 300, Vec3(0, 0, 1), 0.5 * kPi);
    // A second leaf sharing half of the first's samples (its ancestors') and adding its own.
    auto other = spreadSamples(8, 150, Vec3(0, 0, 1), 0.5 * kPi);
    other.insert(other.begin(), samples.begin(), samples.begin() + 150);
    glossy::ReflectCounts warm, replay;
    std::string first, again, mixed;
    // On a thread of its own: its memo starts empty whatever tests ran before in this process.
    std::thread([&] {
      first = project(samples, n, warm);
      again = project(samples, n, replay);
      mixed = project(other, n, warm);
    }).join();
    // The same projections on a thread whose memo is empty: every lobe integrated afresh.
    std::string freshFirst, freshMixed;
    glossy::ReflectCounts cold;
    std::thread([&] {
      freshFirst = project(samples, n, cold);
      glossy::ReflectCounts c2;
      std::thread([&] { freshMixed = project(other, n, c2); }).join();
    }).join();
    // (Compared as booleans: a failure would print megabytes of serialized trees.)
    EXPECT_TRUE(first == again) << "replay differs, n = " << n;
    EXPECT_TRUE(first == freshFirst) << "memo differs from a fresh integration, n = " << n;
    EXPECT_TRUE(mixed == freshMixed) << "partly replayed leaf differs, n = " << n;
    // The replay did come from the memo, with no BRDF evaluated; the second leaf's shared half too.
    EXPECT_EQ(replay.lobesFromMemo, 300u) << n;
    EXPECT_EQ(replay.brdfEvaluations, 0u) << n;
    EXPECT_EQ(warm.lobesFromMemo, 150u) << n;
    EXPECT_EQ(warm.lobesIntegrated, 300u + 150u) << n;
    EXPECT_EQ(cold.lobesFromMemo, 0u) << n;
  }
}

/// Samples in pairs a few hundredths of the merge angle apart (each pair one merged group) and singles
/// far from everything.
std::vector<hr::IncidentSample> pairsAndSingles(double n, int pairs, int singles) {
  std::vector<hr::IncidentSample> out;
  const double m = glossy::mergeAngle(n);
  for (int k = 0; k < pairs + singles; ++k) {
    // Spread over the hemisphere on a spiral, 40 merge angles apart at least.
    double theta = 0.1 + 1.2 * double(k) / double(pairs + singles), phi = 2.4 * double(k);
    Vec3 d = testhost::around(Vec3(0, 0, 1), theta, phi);
    out.push_back(testhost::sample(d, Rgb(1.0 + 0.01 * k)));
    if (k < pairs) out.push_back(testhost::sample(testhost::around(d, 0.05 * m, 0.0), Rgb(0.5)));
  }
  return out;
}

TEST(LobeMemo, AMergedGroupsLobeIsIntegratedButNotKept) {
  // A merged group's direction is weighted by irradiances that change every sweep, so keeping its
  // lobe only filled the memo (the glossy Cornell box: 95 % misses, and a 60 MB budget overrun).
  const double n = 300.0;
  glossy::BasisSpec b = glossy::defaultIsBasis();
  b.haar.maxLevel = 4;
  const auto samples = pairsAndSingles(n, 20, 30);
  std::string first, second;
  glossy::ReflectCounts c1, c2;
  std::thread([&] {
    glossy::LobeSet lobes = glossy::makeLobes(samples, glossy::Frame::world(), Vec3(0, 0, 1), 0.25, Rgb(0.5), n,
                                              glossy::mergeAngle(n), c1);
    ASSERT_EQ(lobes.samples.size(), 50u);
    std::size_t recurring = 0;
    for (const glossy::LobeSample& l : lobes.samples) recurring += l.recurs;
    EXPECT_EQ(recurring, 30u) << "the singles recur, the pairs' groups do not";
    first = bytesOf(glossy::projectLobes(lobes, b, c1));
    EXPECT_EQ(glossy::lobeCache().heldLobes(), 30u);
    second = bytesOf(glossy::projectLobes(lobes, b, c2));
  }).join();
  EXPECT_TRUE(first == second);
  EXPECT_EQ(c2.lobesFromMemo, 30u);
  EXPECT_EQ(c2.lobesIntegrated, 20u);
}

TEST(LobeMemo, StaysWithinTheBoundABudgetSets) {
  glossy::LobeCache::setMaxEntries(0);
  const std::size_t bound = glossy::LobeCache::maxEntries();
  EXPECT_GT(bound, 0u) << "clamped to a few lobes' worth";
  EXPECT_LT(bound, glossy::LobeCache::kMaxEntries);
  std::vector<std::string> bounded, unbounded;
  std::size_t most = 0, mostLobes = 0;
  std::thread([&] {
    for (std::uint64_t seed = 0; seed < 12; ++seed) {
      glossy::ReflectCounts rc;
      bounded.push_back(project(spreadSamples(100 + seed, 200, Vec3(0, 0, 1), 0.5 * kPi), 40.0, rc));
      most = std::max(most, glossy::lobeCache().heldShares());
      mostLobes = std::max(mostLobes, glossy::lobeCache().heldLobes());
    }
  }).join();
  glossy::LobeCache::setMaxEntries(glossy::LobeCache::kMaxEntries);
  std::thread([&] {
    for (std::uint64_t seed = 0; seed < 12; ++seed) {
      glossy::ReflectCounts rc;
      unbounded.push_back(project(spreadSamples(100 + seed, 200, Vec3(0, 0, 1), 0.5 * kPi), 40.0, rc));
    }
    EXPECT_GT(glossy::lobeCache().heldShares(), bound) << "the lobes above do outgrow the small bound";
  }).join();
  EXPECT_LE(most, bound);
  EXPECT_LE(8 * mostLobes, bound);
  EXPECT_TRUE(bounded == unbounded) << "the bound changes what is kept, never a bit of the result";
}

/// makeLobes' grouping by its stated rule, comparing each sample with every group before it.
struct Group {
  Vec3 seed, sum;
  Rgb e;
};
std::vector<Group> scanGroups(const std::vector<hr::IncidentSample>& samples, double merge) {
  struct Item {
    Vec3 mirror;
    Rgb e;
    double w;
    std::size_t index;
  };
  std::vector<Item> items;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    Vec3 wi = samples[i].toSender / glm::length(samples[i].toSender);
    if (!(wi.z > 0.0)) continue;
    const Rgb& e = samples[i].irradiance;
    items.push_back({glossy::mirror(wi, Vec3(0, 0, 1)), e, e.x + e.y + e.z, i});
  }
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.w != b.w ? a.w > b.w : a.index < b.index; });
  std::vector<Group> groups;
  for (const Item& it : items) {
    Group* g = nullptr;
    for (Group& c : groups)
      if (glm::dot(c.seed, it.mirror) >= std::cos(merge)) {
        g = &c;
        break;
      }
    if (!g) {
      groups.push_back({it.mirror, Vec3(0.0), Rgb(0.0)});
      g = &groups.back();
    }
    g->sum += it.w * it.mirror;
    g->e += it.e;
  }
  return groups;
}

TEST(MergeGrid, FindsTheGroupsAScanOfAllGroupsFinds) {
  // Dense clusters of directions, so that most samples have several groups within the angle and the
  // first one must be picked; angles from a sharp lobe's bin to a wide one's.
  for (double merge : {1e-4, 2e-3, 0.02, 0.2}) {
    std::vector<hr::IncidentSample> samples;
    for (int c = 0; c < 6; ++c) {
      auto part = spreadSamples(11 + c, 120, testhost::around(Vec3(0, 0, 1), 0.2 * c, 1.1 * c), 6.0 * merge);
      samples.insert(samples.end(), part.begin(), part.end());
    }
    glossy::ReflectCounts rc;
    glossy::LobeSet lobes =
        glossy::makeLobes(samples, glossy::Frame::world(), Vec3(0, 0, 1), 1.0, Rgb(1.0), 100.0, merge, rc);
    std::vector<Group> want = scanGroups(samples, merge);
    ASSERT_EQ(lobes.samples.size(), want.size()) << merge;
    EXPECT_LT(want.size(), samples.size()) << merge;  // merging did happen
    const double scale = 102.0 / (2.0 * kPi);         // A rho_s (n + 2) / (2 pi), A = rho_s = 1
    for (std::size_t k = 0; k < want.size(); ++k) {
      double len = glm::length(want[k].sum);
      EXPECT_EQ(lobes.samples[k].mirror, len > 0.0 ? want[k].sum / len : want[k].seed) << merge << " group " << k;
      EXPECT_EQ(lobes.samples[k].weight, scale * want[k].e) << merge << " group " << k;
    }
  }
}

}  // namespace

namespace {

using testhost::NodeId;

/// Directions spread over the hemisphere on a spiral, far enough apart that none merge.
std::vector<hr::IncidentSample> spiralSamples(int first, int count) {
  std::vector<hr::IncidentSample> out;
  for (int k = first; k < first + count; ++k) {
    const double t = (k + 0.5) / 48.0;  // 48 directions in all, at least ~15 degrees apart
    out.push_back(testhost::sample(testhost::around(Vec3(0, 0, 1), std::acos(1.0 - 0.97 * t), 2.4 * k),
                                   Rgb(0.3 + 0.1 * (k % 5), 0.2 + 0.05 * (k % 7), 0.4)));
  }
  return out;
}

TEST(ReflectShared, TakesFarSendersAndLeavesNearOnesToBeReAimed) {
  // The floor (1 m^2, its box 1 m x 1 m: half-diagonal 0.707 m) of n = 300, whose leaves resolve
  // max(lobe sqrt(2/300) = 0.082, Haar cell at level 4 = 0.098) rad: a sender seen from the floor
  // within that is one direction for every leaf (farther than 0.707 / 0.098 = 7.2 m); a nearer one
  // is left in front, in its order, for the host to re-aim from each child; an unknown distance is
  // taken as before samples had one.
  testhost::Scene sc(300.0);
  sc.host.node(sc.floor).info.bounds = hr::Aabb{Vec3(-0.5, -0.5, 0.0), Vec3(0.5, 0.5, 0.0)};
  auto a = testhost::configured();
  a->attach(sc.host);
  const double limit = 0.5 * std::sqrt(2.0) / std::max(std::sqrt(2.0 / 300.0), 0.5 * kPi / 16.0);
  auto at = [](double theta, double distance) {
    hr::IncidentSample s = testhost::sample(testhost::around(Vec3(0, 0, 1), theta), Rgb(1.0));
    s.distance = distance;
    return s;
  };
  std::vector<hr::IncidentSample> samples = {at(0.1, 0.0), at(0.2, 0.5), at(0.3, 1.02 * limit),
                                             at(0.4, 0.98 * limit), at(0.5, 20.0), at(0.6, 3.0)};
  ASSERT_EQ(a->reflectShared(sc.floor, samples), 3u);
  EXPECT_EQ(samples[0].distance, 0.5);
  EXPECT_EQ(samples[1].distance, 0.98 * limit);
  EXPECT_EQ(samples[2].distance, 3.0);
  // The leaves get the layer of the three far samples: each leaf's light is theirs alone.
  std::vector<hr::IncidentSample> far = {at(0.1, 0.0), at(0.3, 1.02 * limit), at(0.5, 20.0)};
  auto b = testhost::configured();
  b->attach(sc.host);
  a->reflect(sc.floorLeaves[0], {});
  b->reflect(sc.floorLeaves[0], far);
  ASSERT_TRUE(a->light(sc.floorLeaves[0]) && b->light(sc.floorLeaves[0]));
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(a->light(sc.floorLeaves[0])->power[c], b->light(sc.floorLeaves[0])->power[c],
                1e-9 * b->light(sc.floorLeaves[0])->power[c]);
}

TEST(ReflectShared, LeavesGetWhatTheirWholeSampleListsWouldGive) {
  // The floor (1 m^2) split into four, its first quarter split again. Reflected in layers (the floor's
  // samples once, the quarter's once, each leaf's own) and reflected whole (every leaf all of its and
  // its ancestors' samples), each leaf's power and its intensity in 200 directions agree to rounding.
  testhost::Scene layered(300.0), whole(300.0);
  std::vector<NodeId> deep = layered.host.split(layered.floorLeaves[0]);
  whole.host.split(whole.floorLeaves[0]);
  auto a = testhost::configured(), b = testhost::configured();
  a->attach(layered.host);
  b->attach(whole.host);
  const auto top = spiralSamples(0, 16), mid = spiralSamples(16, 8);
  // Samples of unknown distance are taken whole (none left for the host to carry).
  std::vector<hr::IncidentSample> topTaken = top, midTaken = mid;
  ASSERT_EQ(a->reflectShared(layered.floor, topTaken), 0u);
  ASSERT_EQ(a->reflectShared(layered.floorLeaves[0], midTaken), 0u);
  std::vector<std::pair<NodeId, std::vector<hr::IncidentSample>>> leaves;  // each leaf and its own samples
  for (std::size_t k = 0; k < deep.size(); ++k) leaves.push_back({deep[k], spiralSamples(24 + int(k), 1)});
  for (std::size_t k = 1; k < 4; ++k) leaves.push_back({layered.floorLeaves[k], spiralSamples(28 + 2 * int(k), 2)});
  for (const auto& [leaf, own] : leaves) {
    a->reflect(leaf, own);
    std::vector<hr::IncidentSample> all = top;
    if (leaf.index() >= deep.front().index()) all.insert(all.end(), mid.begin(), mid.end());
    all.insert(all.end(), own.begin(), own.end());
    b->reflect(leaf, all);
  }
  for (const auto& [leaf, own] : leaves) {
    const auto *la = a->light(leaf), *lb = b->light(leaf);
    ASSERT_TRUE(la && lb);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(la->power[c], lb->power[c], 1e-9 * lb->power[c]) << "leaf " << leaf.index();
    double worst = 0.0;
    for (int k = 0; k < 200; ++k) {
      Vec3 d = testhost::around(Vec3(0, 0, 1), std::acos(1.0 - (k + 0.5) / 200.0), 2.4 * k);
      const Rgb ia = a->intensity(leaf, d), ib = b->intensity(leaf, d);
      worst = std::max(worst, hr::maxComponent(glm::abs(ia - ib)) / std::max(1e-12, hr::maxComponent(lb->peak)));
    }
    EXPECT_LT(worst, 1e-5) << "leaf " << leaf.index();  // float cells
  }
  for (const auto& e : a->stats()) {
    if (e.name == "samples_merged_away") {
      EXPECT_EQ(e.value, 0.0);
    }
  }
  // A pull ends its element's layer: a leaf reflected again afterwards (a sweep whose host took no
  // layer) holds only what its own samples give.
  a->pull(layered.floorLeaves[0], deep);
  a->pull(layered.floor, layered.floorLeaves);
  auto c = testhost::configured();
  c->attach(whole.host);
  a->reflect(leaves.front().first, leaves.front().second);
  c->reflect(leaves.front().first, leaves.front().second);
  EXPECT_EQ(a->light(leaves.front().first)->power, c->light(leaves.front().first)->power);
}

}  // namespace
