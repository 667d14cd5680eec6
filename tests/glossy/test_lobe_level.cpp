// The per-material finest Haar level (glossy_extension/include/glossy/lobe_level.h): at defaults a
// material's level is the coarsest whose cells' angular size sqrt(pi/2)/2^L is no larger than its
// lobe's 1/e half-width sqrt(2/n), within [3, 5]; a given --dir-max-level is a hard cap for every
// material; a memory budget holds every level lower; a pull keeps the finest part's level. Checked
// against the closed form and on the distributions a reflection and a pull leave.
#include <gtest/gtest.h>
#include <glossy/lobe_level.h>

#include <cmath>

#include "fake_host.h"

namespace {

using glossy::Rgb;
using glossy::Vec3;
using testhost::NodeId;

double cellSize(int level) { return std::sqrt(glossy::kPi / 2.0) / std::ldexp(1.0, level); }  // rad

TEST(LobeLevel, IsTheCoarsestLevelWhoseCellsAreNoWiderThanTheLobe) {
  for (double n = 1.0; n < 1e5; n *= 1.07) {
    const int level = glossy::lobeLevel(n, 1);
    const double width = std::sqrt(2.0 / n);
    ASSERT_GE(level, glossy::kLobeLevelCoarsest);
    ASSERT_LE(level, glossy::kLobeLevelFinest);
    if (level > glossy::kLobeLevelCoarsest) {
      EXPECT_GT(cellSize(level - 1), width) << "n = " << n << ": one level coarser would do";
    }
    if (level < glossy::kLobeLevelFinest) {
      EXPECT_LE(cellSize(level), width) << "n = " << n << ": cells wider than the lobe";
    }
  }
  // The scenes' materials: glossy Cornell floor and block, three lights' reflector.
  EXPECT_EQ(glossy::lobeLevel(60, 1), 3);
  EXPECT_EQ(glossy::lobeLevel(300, 1), 4);
  EXPECT_EQ(glossy::lobeLevel(500, 1), 5);
  EXPECT_EQ(glossy::lobeLevel(std::nan(""), 1), 3);
  EXPECT_EQ(glossy::lobeLevel(0.0, 2), 3);
}

/// Three glossy leaves (n = 60, 300, 500), each lit by one sample at 30 degrees and reflected; a
/// fourth n = 500 element split into four leaves, lit the same way and pulled.
struct Lit {
  testhost::FakeHost host;
  std::uint32_t broad, middle, sharp;
  NodeId broadLeaf, middleLeaf, sharpLeaf, sharpParent;
  std::unique_ptr<glossy::IlluminationSamples> ext;
  explicit Lit(const std::vector<hr::OptionValue>& o, int budgetLevels = -2) : ext(testhost::configured(o)) {
    broad = host.addMaterial(testhost::glossyMaterial(60.0));
    middle = host.addMaterial(testhost::glossyMaterial(300.0));
    sharp = host.addMaterial(testhost::glossyMaterial(500.0));
    broadLeaf = host.addElement(Vec3(-2, 0, 0), Vec3(0, 0, 1), 1.0, broad);
    middleLeaf = host.addElement(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, middle);
    sharpLeaf = host.addElement(Vec3(2, 0, 0), Vec3(0, 0, 1), 1.0, sharp);
    sharpParent = host.addElement(Vec3(4, 0, 0), Vec3(0, 0, 1), 1.0, sharp);
    host.split(sharpParent);
    host.addCluster({broadLeaf, middleLeaf, sharpLeaf, sharpParent});
    if (budgetLevels > -2) ext->limitDirectionalLevels(budgetLevels);
    ext->attach(host);
    for (NodeId leaf : host.simulatedLeaves(*ext))
      ext->reflect(leaf, std::vector<hr::IncidentSample>{testhost::sample(testhost::around(Vec3(0, 0, 1), 0.52), Rgb(1.0))});
    host.pullAll(*ext);
  }
  int depth(NodeId id) const {
    const auto* l = ext->light(id);
    if (!l) return -1;
    const auto* h = std::get_if<glossy::HaarDistribution>(&l->dist);
    return h ? h->depth() : -1;
  }
  double stat(const std::string& key) const {
    for (const hr::StatEntry& e : ext->stats())
      if (e.name == key) return e.value;
    return -1.0;
  }
};

TEST(LobeLevel, AtDefaultsSharpMaterialsGetFineCellsAndBroadOnesStayCoarse) {
  Lit s({});
  EXPECT_EQ(s.ext->materialLevel(s.broad), 3);
  EXPECT_EQ(s.ext->materialLevel(s.middle), 4);
  EXPECT_EQ(s.ext->materialLevel(s.sharp), 5);
  // A lobe refines down to its material's level where it peaks (the peak hints), and no further.
  EXPECT_EQ(s.depth(s.broadLeaf), 3);
  EXPECT_EQ(s.depth(s.middleLeaf), 4);
  EXPECT_EQ(s.depth(s.sharpLeaf), 5);
  EXPECT_EQ(s.depth(s.sharpParent), 5) << "the pull keeps the sharp leaves' cells";
  EXPECT_EQ(s.stat("dir_max_level_used"), 5.0);
  EXPECT_EQ(s.stat("dir_max_level_material_2"), 5.0);
}

TEST(LobeLevel, AGivenMaximumIsAHardCapForEveryMaterial) {
  for (int given : {2, 3, 4}) {
    Lit s({{"dir-max-level", std::to_string(given)}});
    for (std::uint32_t m : {s.broad, s.middle, s.sharp}) EXPECT_EQ(s.ext->materialLevel(m), given) << "level " << given;
    EXPECT_LE(s.depth(s.sharpLeaf), given);
    EXPECT_LE(s.depth(s.sharpParent), given);
    EXPECT_EQ(s.stat("dir_max_level_used"), double(given));
  }
}

TEST(LobeLevel, AMemoryBudgetHoldsEveryMaterialLower) {
  // dir-min-level 1: a budget of 2 levels above it caps every material at 3; none lifts the cap.
  Lit capped({}, 2);
  for (std::uint32_t m : {capped.broad, capped.middle, capped.sharp}) EXPECT_EQ(capped.ext->materialLevel(m), 3);
  EXPECT_LE(capped.depth(capped.sharpLeaf), 3);
  EXPECT_EQ(capped.stat("dir_max_level_used"), 3.0);
  Lit free({}, -1);
  EXPECT_EQ(free.ext->materialLevel(free.sharp), 5);
  EXPECT_EQ(free.stat("dir_max_level_used"), 5.0);
}

}  // namespace
