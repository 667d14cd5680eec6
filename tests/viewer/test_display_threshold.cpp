// The angle threshold of the glossy display (hr::ExtensionDisplay::update, paper §5.2) on the
// three-lights solution: threshold 0 gives exactly what a fresh display gives (the still images'
// values, to the bit); with a threshold, exactly the vertices whose direction to the eye turned by
// more than it since their last evaluation are re-evaluated (counted by brute force), and the
// others keep their stale values.
#include "view_fixture.h"

namespace {

using viewtest::threeLights;

std::vector<hr::Rgb> values(const hr::ExtensionDisplay& d) { return d.cornerValues(); }

TEST(DisplayThreshold, ZeroIsExactlyTheStillImagesValues) {
  const auto& l = threeLights();
  hr::ExtensionDisplay moving(l.sol, *l.ext);
  ASSERT_GT(moving.vertexCount(), 0u);
  const hr::Vec3 eyes[] = {{-1.2, 1.3, -2.0}, {0.0, 1.25, -2.1}, {1.2, 1.3, -2.0}, {0.3, 1.8, -1.0}};
  for (const hr::Vec3& e : eyes) {
    EXPECT_EQ(moving.update(e, 0.0), moving.vertexCount());
    hr::ExtensionDisplay fresh(l.sol, *l.ext);
    fresh.update(e);
    ASSERT_EQ(values(moving).size(), values(fresh).size());
    for (std::size_t c = 0; c < values(fresh).size(); ++c) ASSERT_EQ(values(moving)[c], values(fresh)[c]) << "corner " << c;
  }
}

TEST(DisplayThreshold, UpdatesExactlyTheVerticesThatTurnedFarEnough) {
  const auto& l = threeLights();
  const double threshold = 3.0;
  hr::ExtensionDisplay d(l.sol, *l.ext);
  // The vertices' positions: every corner of every simulated leaf (duplicates share a vertex).
  std::vector<hr::Vec3> corners;
  for (std::uint32_t i = 0; i < l.sol.elements.size(); ++i)
    if (d.simulated(i))
      for (int k = 0; k < 4; ++k) corners.push_back(l.sol.elements[i].poly.v[std::size_t(std::min(k, l.sol.elements[i].poly.n - 1))]);
  const hr::Vec3 a(0.0, 1.25, -2.1);
  EXPECT_EQ(d.update(a, threshold), d.vertexCount()) << "the first frame evaluates every vertex";
  const std::vector<hr::Rgb> atA = values(d);
  // Moves of growing size: count corners whose direction turned by more than the threshold.
  for (double dx : {0.01, 0.05, 0.12, 0.4}) {
    hr::ExtensionDisplay probe(l.sol, *l.ext);
    probe.update(a, threshold);
    const hr::Vec3 b = a + hr::Vec3(dx, 0.0, 0.0);
    std::size_t updated = probe.update(b, threshold);
    std::size_t turnedCorners = 0;
    for (const hr::Vec3& p : corners)
      if (glm::degrees(std::acos(std::clamp(glm::dot(glm::normalize(a - p), glm::normalize(b - p)), -1.0, 1.0))) > threshold)
        ++turnedCorners;
    // Per corner, fresh or stale, and the count agrees with the corners that turned.
    hr::ExtensionDisplay truthB(l.sol, *l.ext);
    truthB.update(b);
    std::size_t freshCorners = 0;
    for (std::uint32_t c = 0; c < atA.size(); ++c) {
      if (probe.cornerUpdated(c)) {
        ++freshCorners;
        EXPECT_EQ(probe.cornerValues()[c], truthB.cornerValues()[c]) << "a re-evaluated corner has the new eye's value";
      } else {
        EXPECT_EQ(probe.cornerValues()[c], atA[c]) << "a corner below the threshold keeps its value";
      }
    }
    EXPECT_EQ(freshCorners, turnedCorners) << "dx " << dx;
    EXPECT_LE(updated, d.vertexCount());
    EXPECT_EQ(updated == 0, turnedCorners == 0);
    RecordProperty("updated_at_dx_" + std::to_string(int(dx * 100)) + "cm", int(updated));
  }
  // Small steps that add up: each vertex is compared with its own last evaluation, not the last frame.
  hr::ExtensionDisplay creep(l.sol, *l.ext);
  creep.update(a, threshold);
  std::size_t total = 0;
  for (int i = 1; i <= 40; ++i) total += creep.update(a + hr::Vec3(0.01 * i, 0.0, 0.0), threshold);
  EXPECT_GT(total, 0u) << "40 steps of 1 cm turn the view by more than 3 degrees somewhere";
}

}  // namespace
