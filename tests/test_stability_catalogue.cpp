// The stability catalogue (issue 17): hard cases a user meets, each solved with the glossy
// extension and required to stay finite everywhere with its energy within 1 % (or to stop with a
// message that names the fault). Cases covered elsewhere are listed in docs/solver.md's catalogue:
// closed boxes of albedo 0.99 and 0.999 (Furnace.*), 1.0 refused (CannotAbsorb.*), touching and
// sliver geometry (Robustness.TouchingCoplanarAndSliverGeometry), diffuse scenes scaled by 1e+-3
// (Robustness.ScaledScenesGiveScaleFreeAnswers), close and coplanar lamps (NearField.*).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "helpers.h"
#include "registry.h"

namespace {

std::unique_ptr<hr::Extension> makeIs() {
  auto ext = adapters::findExtension("is").make();
  ext->configure({});
  return ext;
}

double imbalance(const testutil::Solved& s, int c) {
  return (s.stats.emittedW[c] - s.stats.absorbedW[c] - s.stats.escapedW[c]) / s.stats.emittedW[c];
}

void expectStable(const testutil::Solved& s, const char* what) {
  for (const hr::Rgb& b : s.solver->radiosity()) ASSERT_TRUE(hr::allFinite(b)) << what;
  for (int c = 0; c < 3; ++c) EXPECT_LT(std::abs(imbalance(s, c)), 0.01) << what << ", channel " << c;
  EXPECT_FALSE(s.stats.diverged) << what;
}

const char* kMaterials = R"("l": { "emission": [5,5,5] }, "w": { "diffuse": [0.6,0.6,0.6] },
    "g": { "diffuse": [0.2,0.2,0.2], "specular": [0.6,0.6,0.6], "exponent": 200 },
    "sharp": { "diffuse": [0.1,0.1,0.1], "specular": [0.8,0.8,0.8], "exponent": 5000 })";

std::string scene(const std::string& objects, const std::string& extraMaterials = "") {
  return std::string(R"({ "materials": { )") + kMaterials + extraMaterials + R"( }, "objects": [ )" + objects + " ] }";
}

hr::SolverOptions options(double eps = 1e-3, int maxLevel = 6) {
  hr::SolverOptions o;
  o.eps = eps;
  o.maxLevel = maxLevel;
  return o;
}

/// A glossy floor whose edge meets two smaller quads of a wall side by side: the wall's shared
/// vertex sits in the middle of the floor's edge (a T-junction), where elements of the two objects
/// never line up.
TEST(StabilityCatalogue, TJunctionBetweenGlossyAndDiffuse) {
  auto ext = makeIs();
  auto s = testutil::solveText(
      scene(R"({ "type": "quad", "material": "l", "vertices": [[0.8,1.5,0.8],[1.2,1.5,0.8],[1.2,1.5,1.2],[0.8,1.5,1.2]] },
               { "type": "quad", "material": "g", "vertices": [[0,0,0],[0,0,2],[2,0,2],[2,0,0]] },
               { "type": "quad", "material": "w", "vertices": [[0,0,0],[0.7,0,0],[0.7,1,0],[0,1,0]] },
               { "type": "quad", "material": "w", "vertices": [[0.7,0,0],[2,0,0],[2,1,0],[0.7,1,0]] })"),
      options(), ext.get());
  expectStable(s, "T-junction");
}

/// A 1 mm square lamp of 1 W in a closed 10 m room: a source 10^4 times smaller than the walls it
/// lights, every link from it in the far field but its emitter power concentrated in one element.
/// Closed, so all of the power must be absorbed. Measured at the default eps 2e-4: imbalance 0.63 %
/// (0.17 % without the extension); at eps 1e-3 1.8 %, so the catalogue runs at the default.
TEST(StabilityCatalogue, OneMillimetreSourceInATenMetreRoom) {
  // L_e = 1 W / (pi A) with A = 1e-6 m^2.
  const std::string lamp = R"(, "tiny": { "emission": [318309.9,318309.9,318309.9] })";
  auto ext = makeIs();
  auto s = testutil::solveText(
      scene(R"({ "type": "box", "material": "w", "facing": "inward", "min": [0,0,0], "max": [10,10,10] },
               { "type": "quad", "material": "g", "vertices": [[1,1,1],[1,1,9],[9,1,9],[9,1,1]] },
               { "type": "quad", "material": "tiny", "vertices": [[5,9.5,5],[5.001,9.5,5],[5.001,9.5,5.001],[5,9.5,5.001]] })",
            lamp),
      options(2e-4, 8), ext.get());
  expectStable(s, "1 mm source");
  EXPECT_NEAR(s.stats.emittedW.y, 1.0, 1e-3);
  for (int c = 0; c < 3; ++c) EXPECT_LT(s.stats.escapedW[c], 1e-3 * s.stats.emittedW[c]) << "a closed room";
}

/// A lamp 1 cm under a ceiling, facing it: the ceiling's bright spot is hidden from the walls by the
/// lamp, and a partly visible link from an inner ceiling element sends the children its rays saw at
/// their mean, bright spot and all. Each such link held its error to the per-link tolerance with
/// the same sign, and the room made 9.7 % of its light at eps 2e-3 (refine.cpp, powerBudget; 1/K in
/// the rays per link). Diffuse and with the extension, at eps 2e-3: within the audit's 2 %. Measured:
/// -1.50 % diffuse, -1.49 % with the extension (-9.26 % and -9.45 % without the area budget).
TEST(StabilityCatalogue, ALampFacingTheCeilingMakesNoLightAtACoarseThreshold) {
  const std::string room = R"({ "type": "box", "material": "w", "facing": "inward", "min": [0,0,0], "max": [3,3,2.5] },
      { "type": "quad", "material": "l", "vertices": [[1.2,1.2,2.49],[1.8,1.2,2.49],[1.8,1.8,2.49],[1.2,1.8,2.49]] },
      { "type": "quad", "material": "g", "vertices": [[0.5,0.5,0.8],[1,0.5,0.8],[1,1,0.8],[0.5,1,0.8]] })";
  for (bool glossy : {false, true}) {
    auto ext = glossy ? makeIs() : nullptr;
    auto s = testutil::solveText(scene(room), options(2e-3, 6), ext.get());
    const char* what = glossy ? "lamp facing the ceiling, is" : "lamp facing the ceiling, diffuse";
    std::printf("%s: imbalance %.2f %%\n", what, 100.0 * imbalance(s, 1));
    for (const hr::Rgb& b : s.solver->radiosity()) ASSERT_TRUE(hr::allFinite(b)) << what;
    for (int c = 0; c < 3; ++c) EXPECT_LT(std::abs(imbalance(s, c)), 0.02) << what << ", channel " << c;
  }
}

/// A near-mirror of exponent 5000 as a 20 x 20 m floor under a small lamp: the lobe (half-width
/// under 2 degrees) is far narrower than any element's solid angle from its neighbours.
TEST(StabilityCatalogue, PhongExponent5000OnALargeFloor) {
  auto ext = makeIs();
  auto s = testutil::solveText(
      scene(R"({ "type": "quad", "material": "l", "vertices": [[-0.5,3,-0.5],[0.5,3,-0.5],[0.5,3,0.5],[-0.5,3,0.5]] },
               { "type": "quad", "material": "sharp", "vertices": [[-10,0,-10],[-10,0,10],[10,0,10],[10,0,-10]] },
               { "type": "quad", "material": "w", "vertices": [[-10,0,-10],[10,0,-10],[10,6,-10],[-10,6,-10]] })"),
      options(), ext.get());
  expectStable(s, "exponent 5000");
}

/// Two quads overlapping in one plane (z-fighting), one glossy and one diffuse: each sees the
/// other at zero distance and zero angle.
TEST(StabilityCatalogue, CoplanarOverlappingGlossyAndDiffuseQuads) {
  auto ext = makeIs();
  auto s = testutil::solveText(
      scene(R"({ "type": "quad", "material": "l", "vertices": [[0.8,1.5,0.8],[1.2,1.5,0.8],[1.2,1.5,1.2],[0.8,1.5,1.2]] },
               { "type": "quad", "material": "g", "vertices": [[0,0,0],[0,0,2],[2,0,2],[2,0,0]] },
               { "type": "quad", "material": "w", "vertices": [[1,0,1],[1,0,3],[3,0,3],[3,0,1]] })"),
      options(), ext.get());
  expectStable(s, "coplanar overlap");
}

/// A glossy scene scaled by 1e-3 and 1e3 (the same lamp radiance): radiosity is scale-free, so the
/// glossy floor's mean radiosity must not move with the unit of length.
TEST(StabilityCatalogue, GlossySceneScaledByAThousandEitherWay) {
  auto at = [](double k) {
    // snprintf, not operator+ on temporaries: GCC 12 warns falsely (-Wrestrict) on the latter.
    char buf[1024];
    std::snprintf(buf, sizeof buf,
                  R"({ "type": "quad", "material": "l", "vertices": [[%g,%g,%g],[%g,%g,%g],[%g,%g,%g],[%g,%g,%g]] },
                     { "type": "quad", "material": "g", "vertices": [[0,0,0],[0,0,%g],[%g,0,%g],[%g,0,0]] },
                     { "type": "quad", "material": "w", "vertices": [[0,0,0],[%g,0,0],[%g,%g,0],[0,%g,0]] })",
                  0.8 * k, 1.5 * k, 0.8 * k, 1.2 * k, 1.5 * k, 0.8 * k, 1.2 * k, 1.5 * k, 1.2 * k, 0.8 * k, 1.5 * k,
                  1.2 * k, 2 * k, 2 * k, 2 * k, 2 * k, 2 * k, 2 * k, 1.5 * k, 1.5 * k);
    return scene(buf);
  };
  double mean[3];
  const double scales[3] = {1e-3, 1.0, 1e3};
  for (int i = 0; i < 3; ++i) {
    auto ext = makeIs();
    auto s = testutil::solveText(at(scales[i]), options(), ext.get());
    expectStable(s, "scaled");
    mean[i] = s.meanRadiosity(2).y;  // the wall, lit by the lamp and by the glossy floor
  }
  EXPECT_NEAR(mean[0] / mean[1], 1.0, 0.01);
  EXPECT_NEAR(mean[2] / mean[1], 1.0, 0.01);
}

/// An extension whose light turns NaN on one leaf after its second reflection stands for any bug
/// that puts a NaN into a distribution: the solve must stop, and say where (the extension's
/// light, the element, its object and material), instead of writing a NaN or silently zeroing it.
class Poisoned final : public hr::Extension {
 public:
  std::string_view name() const override { return "poisoned"; }
  bool simulates(const hr::MaterialInfo& m) const override { return m.specular.y > 0.0; }
  void attach(const hr::HostView& v) override {
    view_ = &v;
    power_.resize(v.elementCount(), 0.0);
  }
  hr::Rgb intensity(hr::NodeId n, const hr::Vec3& dir) const override {
    if (!view_ || n.isCluster() || n.index() >= power_.size()) return hr::Rgb(0.0);
    return hr::Rgb(power_[n.index()] * std::max(0.0, glm::dot(view_->info(n).normal, dir)) / hr::kPi);
  }
  // Reflections of one sweep run concurrently: the 41st of the solve poisons its leaf, for good.
  void reflect(hr::NodeId leaf, std::span<const hr::IncidentSample> samples) override {
    if (!view_) return;
    double E = 0.0;
    for (const auto& smp : samples) E += smp.irradiance.y;
    std::uint32_t none = hr::kNone;
    if (reflects_.fetch_add(1) + 1 == 41) poisonedLeaf_.compare_exchange_strong(none, leaf.index());
    power_[leaf.index()] = leaf.index() == poisonedLeaf_.load() ? kNaN : 0.3 * view_->info(leaf).area * E;
  }
  hr::Rgb reflectedPower(hr::NodeId leaf) const override {
    return hr::Rgb(leaf.index() < power_.size() ? power_[leaf.index()] : 0.0);
  }
  double powerChange() const override {
    double sum = 0.0;  // NaN once a leaf is poisoned, as a real extension's sum over its leaves would be
    for (double p : power_) sum += p;
    return sum;
  }
  std::atomic<std::uint32_t> poisonedLeaf_{hr::kNone};

 private:
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const hr::HostView* view_ = nullptr;
  std::vector<double> power_;
  std::atomic<int> reflects_{0};
};

TEST(StabilityCatalogue, ANaNInADistributionStopsTheSolveAndIsNamed) {
  Poisoned ext;
  std::string message;
  try {
    testutil::solveText(
        scene(R"({ "type": "quad", "material": "l", "vertices": [[0.8,1.5,0.8],[1.2,1.5,0.8],[1.2,1.5,1.2],[0.8,1.5,1.2]] },
                 { "type": "quad", "material": "g", "vertices": [[0,0,0],[0,0,2],[2,0,2],[2,0,0]] })"),
        options(1e-3, 4), &ext);
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  ASSERT_NE(ext.poisonedLeaf_.load(), hr::kNone) << "the poison was never injected";
  ASSERT_FALSE(message.empty()) << "the solve finished with a NaN in the extension's light";
  EXPECT_NE(message.find("extension's (poisoned)"), std::string::npos) << message;
  EXPECT_NE(message.find("element " + std::to_string(ext.poisonedLeaf_.load())), std::string::npos) << message;
  EXPECT_NE(message.find("object 1, material \"g\""), std::string::npos) << message;
}


/// A memory budget that cuts refinement short keeps links the oracle wanted split. A 2 x 2 m room
/// open at its sides, a lamp 1 cm under the ceiling facing it, two 3 cm stainless discs 5 mm apart
/// and a larger glossy disc, capped at a few thousand links (testOnlyMaxLinks: capRound's cap,
/// repeatable): links between the room's halves stay at the cluster level with overlapping bounding
/// spheres, where the far-field model handed the floor's cluster 1.75 times the ceiling's power. So
/// capped, the diffuse core created 3.7 % of the light and the glossy solve diverged (imbalance
/// -2e24); with `--memory-mb` 40-50, 5-10 % was created (exit 3). Such links now carry what rays
/// measure (measureOverlap). Kept links the oracle wanted split still misplace light (the ceiling's
/// bright spot over the lamp sends as the ceiling's mean, so ~20 % is lost here): the requirement is
/// that no light is created beyond the audit's 2 % bar, nothing diverges, and a loss beyond the bar
/// is reported (energyOk false, exit 3 from the command line).
TEST(StabilityCatalogue, ATightLinkCapCreatesNoLightAndSaysWhenItLosesSome) {
  const std::string json = R"({ "materials": {
      "lamp": { "emission": [20,20,20] }, "wall": { "diffuse": [0.5,0.5,0.5] },
      "steel": { "diffuse": [0.14,0.14,0.14], "specular": [0.56,0.56,0.56], "exponent": 10000 } },
    "objects": [
      { "type": "quad", "material": "lamp", "vertices": [[-0.1,-0.1,0.99],[0.1,-0.1,0.99],[0.1,0.1,0.99],[-0.1,0.1,0.99]] },
      { "type": "quad", "material": "wall", "vertices": [[-1,-1,0],[1,-1,0],[1,1,0],[-1,1,0]] },
      { "type": "quad", "material": "wall", "vertices": [[-1,-1,1],[-1,1,1],[1,1,1],[1,-1,1]] },
      { "type": "disk", "material": "steel", "center": [0,0,0.3], "normal": [0.3,0,1], "radius": 0.03 },
      { "type": "disk", "material": "steel", "center": [0,0,0.305], "normal": [-0.3,0,-1], "radius": 0.03 },
      { "type": "disk", "material": "steel", "center": [0.3,0,0.2], "normal": [0,0,1], "radius": 0.3 } ],
    "settings": { "tessellation": 8 } })";
  for (std::size_t cap : {2000, 4000}) {
    for (bool glossy : {false, true}) {
      auto ext = glossy ? makeIs() : nullptr;
      hr::SolverOptions o = options(1e-6, 8);
      o.testOnlyMaxLinks = cap;
      auto s = testutil::solveText(json, o, ext.get());
      const std::string what = std::string(glossy ? "is" : "diffuse") + ", cap " + std::to_string(cap);
      for (const hr::Rgb& b : s.solver->radiosity()) ASSERT_TRUE(hr::allFinite(b)) << what;
      EXPECT_FALSE(s.stats.diverged) << what;
      for (int c = 0; c < 3; ++c) {
        EXPECT_GT(imbalance(s, c), -0.02) << what << ": light created, channel " << c;
        if (std::abs(imbalance(s, c)) > 0.03) {
          EXPECT_FALSE(s.stats.energyOk) << what << ": a loss not reported";
        }
      }
    }
  }
}

}  // namespace
