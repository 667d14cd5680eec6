// The hook interface: an extension that simulates no material must leave the core's answer bit for
// bit as it was and must never be asked for light; the host attaches it after every refinement pass.
#include <gtest/gtest.h>

#include <atomic>

#include "helpers.h"

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

}  // namespace
