// The hook interface: an extension that simulates no material must leave the core's answer bit for
// bit as it was and must never be asked for light; the host attaches it after every refinement pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <vector>

#include "helpers.h"
#include "sample_recorder.h"

namespace {

const char* kScene = testutil::kParallelPlates;

class IdleExtension final : public hr::Extension {
 public:
  std::string_view name() const override { return "idle"; }
  void attach(const hr::HostView& v) override { ++attaches, nodes = v.elementCount(); }
  hr::Rgb intensity(hr::NodeId, const hr::Vec3&) const override {
    ++asked;
    return hr::Rgb(1.0);
  }
  void reflect(hr::NodeId, std::span<const hr::IncidentSample>) override { ++reflects; }
  int attaches = 0, reflects = 0;
  mutable std::atomic<int> asked{0};
  std::size_t nodes = 0;
};

TEST(Hooks, AnExtensionThatSimulatesNothingChangesNothing) {
  hr::SolverOptions o;
  o.eps = 1e-4;
  auto plain = testutil::solveText(kScene, o);
  IdleExtension ext;
  auto hooked = testutil::solveText(kScene, o, &ext);
  EXPECT_GT(ext.attaches, 0);
  EXPECT_EQ(ext.nodes, hooked.h->elements().size());
  EXPECT_EQ(ext.asked.load(), 0);  // no simulated material: its intensity is never read
  EXPECT_EQ(ext.reflects, 0);
  EXPECT_EQ(plain.meanRadiosity(1), hooked.meanRadiosity(1));
}

/// An extension that creates energy: each simulated leaf sends gain times the power it receives,
/// as a Lambertian lobe. Physically impossible for gain > 1; it stands for any broken extension.
class Amplifier final : public hr::Extension {
 public:
  explicit Amplifier(double gain) : gain_(gain) {}
  std::string_view name() const override { return "amplifier"; }
  bool simulates(const hr::MaterialInfo& m) const override { return m.specular.y > 0.0; }
  void attach(const hr::HostView& v) override {
    view_ = &v;
    elementPower_.resize(v.elementCount(), 0.0);
    clusterPower_.resize(v.clusterCount(), 0.0);
    change_.resize(v.elementCount(), 0.0);
  }
  // The host's first push (emitters only) comes before the first attach: nothing to hold yet.
  hr::Rgb intensity(hr::NodeId n, const hr::Vec3& dir) const override {
    if (!view_) return hr::Rgb(0.0);
    const hr::NodeInfo i = view_->info(n);
    const double P = power(n);
    // Lambertian: I = P cos / pi for a planar node; a cluster sends its power evenly, P / (4 pi).
    return hr::Rgb(i.planar ? P * std::max(0.0, glm::dot(i.normal, dir)) / hr::kPi : P / (4.0 * hr::kPi));
  }
  void reflect(hr::NodeId leaf, std::span<const hr::IncidentSample> samples) override {
    if (!view_) return;
    double E = 0.0;
    for (const auto& smp : samples) E += smp.irradiance.y;
    const double P = gain_ * view_->info(leaf).area * E;
    change_[leaf.index()] = std::abs(P - power(leaf));
    power(leaf) = P;
  }
  void pull(hr::NodeId n, std::span<const hr::NodeId> kids) override {
    if (!view_) return;
    double P = 0.0;
    for (hr::NodeId k : kids) P += power(k);
    power(n) = P;
  }
  double powerChange() const override {
    double sum = 0.0;
    for (double c : change_) sum += c;
    return sum;
  }

 private:
  double& power(hr::NodeId n) { return n.isCluster() ? clusterPower_[n.index()] : elementPower_[n.index()]; }
  // The oracle asks about nodes a refinement pass just made, before attach sizes the tables: dark.
  double power(hr::NodeId n) const {
    const auto& v = n.isCluster() ? clusterPower_ : elementPower_;
    return n.index() < v.size() ? v[n.index()] : 0.0;
  }
  double gain_;
  const hr::HostView* view_ = nullptr;
  std::vector<double> elementPower_, clusterPower_, change_;
};

// The core's safety net, generic: a solve whose residual keeps growing beyond the emitted power is
// creating energy; it stops as diverging within a few iterations instead of running on to the
// iteration limit (the glossy Soda Shoppe once grew ~10x per iteration to 3 million links).
TEST(Hooks, ASolveThatCreatesEnergyStopsAsDiverging) {
  const char* scene = R"({ "materials": { "l": { "emission": [5,5,5] },
      "amp": { "diffuse": [0.1,0.1,0.1], "specular": [0.5,0.5,0.5], "exponent": 10 } },
    "objects": [
      { "type": "quad", "material": "l", "vertices": [[0.45,0.1,0.45],[0.55,0.1,0.45],[0.55,0.1,0.55],[0.45,0.1,0.55]] },
      { "type": "quad", "material": "amp", "vertices": [[0,0,0],[0,0,1],[1,0,1],[1,0,0]] },
      { "type": "quad", "material": "amp", "vertices": [[0,0.2,0],[1,0.2,0],[1,0.2,1],[0,0.2,1]] } ] })";
  hr::SolverOptions o;
  o.eps = 1e-2;
  o.maxLevel = 2;
  o.maxIterations = 40;
  Amplifier amp(10.0);
  auto s = testutil::solveText(scene, o, &amp);
  EXPECT_TRUE(s.stats.diverged);
  EXPECT_FALSE(s.stats.converged);
  EXPECT_LT(s.stats.iterations, o.maxIterations);
  ASSERT_GE(s.stats.history.size(), 4u);
  EXPECT_GT(s.stats.history.back().residualW, hr::luminance(s.stats.emittedW));
  // And the same scene without the amplifier is not flagged (its plates reflect 0.1 diffusely).
  auto plain = testutil::solveText(scene, o);
  EXPECT_FALSE(plain.stats.diverged);
  EXPECT_TRUE(plain.stats.converged);
}

// A sample names its sender's normal when the sender is a flat element (the display carries its
// foreshortening to the point it shows: hr::IncidentSample::senderNormal) and its shape (the
// rectangle of one of its pieces: at eps 2e-5 the lamp's links split), gathering and shooting.
TEST(Hooks, ASampleNamesItsFlatSendersNormal) {
  for (hr::Iteration it : {hr::Iteration::Gather, hr::Iteration::Shoot}) {
    hr::SolverOptions o;
    o.eps = 2e-5;
    o.iteration = it;
    testutil::SampleRecorder rec;
    auto s = testutil::solveText(testutil::kTiltedLampOverGlossyFloor, o, &rec);
    const testutil::LampSamples l = testutil::samplesNamingTheLamp(rec, true);
    std::printf("%s: %zu samples, %zu name the lamp's normal, %zu another, %zu a shape not its pieces' "
                "(finest: a side halved %d times)\n",
                it == hr::Iteration::Gather ? "gather" : "shoot", rec.seen.size(), l.named, l.wrong,
                l.misshapen, l.finest);
    EXPECT_GT(l.named, 0u);
    EXPECT_EQ(l.wrong, 0u);
    EXPECT_EQ(l.misshapen, 0u);
    EXPECT_GT(l.finest, 0);  // pieces, not only the whole lamp
  }
}

}  // namespace
