// The hooks' threading contract, exercised with std::thread: reflect concurrently across leaves,
// pull concurrently across disjoint subtrees, and the const queries from many threads at once, give
// bit for bit the answers of a serial run (the solution file's bytes, powerChange, every counter
// but CPU time, and every query), whatever the number of threads.
#include <gtest/gtest.h>

#include <random>
#include <thread>

#include "directions.h"
#include "fake_host.h"
#include "../saved_bytes.h"

namespace {

using glossy::Rgb;
using glossy::Vec3;
using glossy::kPi;
using testhost::NodeId;

/// A floor of 4 x 4 x 4 = 64 glossy leaves under one cluster with a glossy wall and a diffuse leaf.
struct Room {
  testhost::FakeHost host;
  NodeId floor, wall;
  std::vector<NodeId> quadrants;
  Room() {
    std::uint32_t g = host.addMaterial(testhost::glossyMaterial(200.0)), d = host.addMaterial(testhost::diffuseMaterial());
    floor = host.addElement(Vec3(0.0), Vec3(0, 0, 1), 4.0, g);
    quadrants = host.split(floor);
    for (NodeId q : quadrants)
      for (NodeId c : host.split(q)) host.split(c);
    wall = host.addElement(Vec3(-1, 0, 1), Vec3(1, 0, 0), 2.0, g);
    NodeId matte = host.addElement(Vec3(1, 0, 1), Vec3(-1, 0, 0), 2.0, d);
    host.addCluster({floor, wall, matte});
  }
  /// The samples of a leaf, the same whoever asks.
  std::vector<hr::IncidentSample> samplesOf(NodeId leaf) const {
    std::mt19937_64 g(leaf.value * 7919ull + 1);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Vec3 n = host.info(leaf).normal;
    std::vector<hr::IncidentSample> s;
    for (int k = 0; k < 12; ++k) s.push_back(testhost::sample(testhost::around(n, std::acos(u(g)), 2 * kPi * u(g)), Rgb(u(g), u(g), 1.0)));
    return s;
  }
};

std::unique_ptr<glossy::IlluminationSamples> solve(const Room& room, int threads, const char* basis) {
  auto ext = testhost::configured({{"basis", basis}});
  ext->attach(room.host);
  auto leaves = room.host.simulatedLeaves(*ext);
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (std::size_t i = std::size_t(t); i < leaves.size(); i += std::size_t(threads)) ext->reflect(leaves[i], room.samplesOf(leaves[i]));
    });
  for (auto& th : pool) th.join();
  pool.clear();
  // The four floor quadrants are disjoint subtrees: pulled at the same time, then the rest.
  for (std::size_t q = 0; q < room.quadrants.size(); ++q) pool.emplace_back([&, q] { room.host.pullFrom(*ext, room.quadrants[q]); });
  for (auto& th : pool) th.join();
  ext->pull(room.floor, room.host.children(room.floor));
  ext->pull(room.host.root(), room.host.children(room.host.root()));
  return ext;
}

std::vector<double> counters(const hr::Extension& ext) {
  std::vector<double> out;
  for (const auto& s : ext.stats())
    if (s.name.find("cpu_seconds") == std::string::npos) out.push_back(s.value);
  return out;
}

/// Answers to every const query over all nodes, computed on `threads` threads (interleaved).
std::vector<double> queries(const hr::Extension& ext, const Room& room, int threads) {
  std::vector<NodeId> nodes;
  for (std::uint32_t i = 0; i < room.host.elements.size(); ++i) nodes.push_back(NodeId{i});
  nodes.push_back(room.host.root());
  const int perNode = 200, values = 21;
  std::vector<double> out(nodes.size() * perNode * values);
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (std::size_t i = std::size_t(t); i < nodes.size(); i += std::size_t(threads)) {
        std::mt19937_64 g(i);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        for (int k = 0; k < perNode; ++k) {
          double* o = &out[(i * perNode + std::size_t(k)) * values];
          Vec3 d = testdirs::sphere(g), s;
          // reflectedPower is a quadrature for the fixed bases: once per node is enough.
          Rgb r[6] = {ext.intensity(nodes[i], d), ext.intensityBound(nodes[i], d, std::cos(0.2)), ext.radiance(nodes[i], d),
                      k == 0 ? ext.reflectedPower(nodes[i]) : Rgb(0.0), ext.sampleExitant(nodes[i], u(g), u(g), s), s};
          for (int j = 0; j < 6; ++j)
            for (int c = 0; c < 3; ++c) o[3 * j + c] = r[j][c];
          o[18] = double(ext.coefficients(nodes[i]));
          o[19] = ext.powerChange();
          o[20] = 0.0;
        }
      }
    });
  for (auto& th : pool) th.join();
  return out;
}

TEST(IsThreads, ConcurrentHooksGiveTheSerialAnswer) {
  Room room;
  for (const char* basis : {"haar", "tetra", "sh"}) {
    auto serial = solve(room, 1, basis);
    const std::string bytes = testutil::savedBytes(*serial);
    const auto reference = queries(*serial, room, 1);
    EXPECT_GT(serial->powerChange(), 0.0);
    for (int threads : {2, 4, 7}) {
      auto parallel = solve(room, threads, basis);
      EXPECT_EQ(testutil::savedBytes(*parallel), bytes) << basis << ", " << threads << " threads";
      EXPECT_EQ(parallel->powerChange(), serial->powerChange()) << basis << ", " << threads << " threads";
      EXPECT_EQ(counters(*parallel), counters(*serial)) << basis << ", " << threads << " threads";
      EXPECT_EQ(queries(*parallel, room, threads), reference) << basis << ", " << threads << " threads";
    }
  }
}

TEST(IsThreads, StatisticsCountWhatHappened) {
  Room room;
  auto ext = solve(room, 3, "haar");
  std::map<std::string, double> s;
  for (const auto& e : ext->stats()) s[e.name] = e.value;
  const double leaves = 65.0;  // 64 floor leaves and the wall
  EXPECT_EQ(s["reflect_leaf_visits"], leaves);
  EXPECT_EQ(s["samples_received_total"], 12.0 * leaves);
  EXPECT_EQ(s["samples_peak_per_reflect"], 12.0);
  EXPECT_EQ(s["samples_dropped_no_front_light"], 0.0) << "every sample comes from above its leaf";
  EXPECT_GE(s["samples_merged_away"], 0.0);
  EXPECT_LT(s["samples_merged_away"], s["samples_received_total"]);
  EXPECT_EQ(s["pull_node_visits"], 16.0 + 4.0 + 1.0 + 1.0);
  EXPECT_EQ(s["distributions"], leaves + 16.0 + 4.0 + 1.0 + 1.0);
  EXPECT_EQ(s["distributions_at_leaves"], leaves);
  EXPECT_GT(s["brdf_evaluations"], 0.0);
  EXPECT_GT(s["coefficients_total"], s["coefficients_peak_per_distribution"]);
  EXPECT_GT(s["bytes"], s["coefficients_total"] * 16.0);
  EXPECT_GT(s["reflect_cpu_seconds_summed_over_threads"], 0.0);
  for (const auto& e : ext->stats()) EXPECT_TRUE(std::isfinite(e.value)) << e.name;
}

}  // namespace
