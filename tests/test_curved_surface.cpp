// Exact normals of curved primitives (hr/curved_surface.h) against closed forms, the display shading
// the BRIGHT-like host's tessellated sphere at them, and the "surfaces" section refused when damaged.
#include <gtest/gtest.h>
#include <hr/curved_surface.h>
#include <hr/solution.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "helpers.h"
#include "normal_probe.h"

namespace {

using testutil::degreesBetween;

hr::Object sphere(const hr::Vec3& c, double r) {
  hr::Object o;
  o.type = hr::PrimitiveType::Sphere;
  o.center = c, o.radius = r;
  return o;
}

hr::CurvedSurface only(const hr::Object& o) {
  hr::Scene s;
  s.objects = {o};
  return hr::curvedSurfaces(s).at(0);
}

TEST(CurvedSurface, NormalsMatchTheClosedForms) {
  // A sphere: (p - c) / r at any point along the radius (on, inside or outside the surface).
  const hr::CurvedSurface s = only(sphere({1, 2, 3}, 0.5));
  for (const hr::Vec3 d : {hr::Vec3(1, 0, 0), hr::Vec3(0.3, -0.4, 0.866), hr::Vec3(0, 0, -1)})
    for (double t : {0.45, 0.5, 0.7}) EXPECT_LT(degreesBetween(s.normalAt(hr::Vec3(1, 2, 3) + t * glm::normalize(d)), d), 1e-9);
  EXPECT_EQ(s.normalAt({1, 2, 3}), hr::Vec3(0.0)) << "undefined at the centre";
  // Scaled by (2, 1, 0.5) it is an ellipsoid with semi-axes (a, b, c) = (1, 0.5, 0.25) about the
  // origin: the normal at (x, y, z) is along (x / a^2, y / b^2, z / c^2).
  hr::Object e = sphere({0, 0, 0}, 0.5);
  e.transform.scale = {2, 1, 0.5};
  const hr::CurvedSurface el = only(e);
  const hr::Vec3 p = glm::normalize(hr::Vec3(0.4, 0.7, -0.5)) * hr::Vec3(1, 0.5, 0.25);
  EXPECT_LT(degreesBetween(el.normalAt(p), hr::Vec3(p.x / 1.0, p.y / 0.25, p.z / 0.0625)), 1e-9);
  // A cone from radius 1 at z = 0 to 0.5 at z = 2 along +z: its side rises 2 for every 0.5 it
  // narrows, so the outward normal at azimuth phi is (2 cos phi, 2 sin phi, 0.5), normalised.
  hr::Object c;
  c.type = hr::PrimitiveType::Cone;
  c.base = {0, 0, 0}, c.axis = {0, 0, 1}, c.radius = 1.0, c.radius2 = 0.5, c.height = 2.0;
  const hr::CurvedSurface cone = only(c);
  for (double phi : {0.0, 1.0, 2.5, 4.0}) {
    const hr::Vec3 q(0.75 * std::cos(phi), 0.75 * std::sin(phi), 1.0);
    EXPECT_LT(degreesBetween(cone.normalAt(q), hr::Vec3(2 * std::cos(phi), 2 * std::sin(phi), 0.5)), 1e-9) << phi;
  }
  EXPECT_EQ(cone.normalAt({0, 0, 1}), hr::Vec3(0.0)) << "undefined on the axis";
  // A cylinder is radial, and inward turns it round.
  c.type = hr::PrimitiveType::Cylinder;
  c.inward = true;
  EXPECT_LT(degreesBetween(only(c).normalAt({0, 0.9, 0.3}), hr::Vec3(0, -1, 0)), 1e-9);
  // Flat primitives have none.
  hr::Object q;
  q.type = hr::PrimitiveType::Quad;
  EXPECT_EQ(only(q).kind, hr::CurvedKind::None);
  EXPECT_EQ(only(q).normalAt({0, 0, 0}), hr::Vec3(0.0));
}

TEST(CurvedSurface, ARayIsMovedFromAFacetOntoTheSurface) {
  // A viewer's ray that hit a point 1 cm inside the sphere (radius 0.5 about (1, 2, 3)), on a chord,
  // meets the sphere itself where it entered it: the root of |p + t d - c| = r furthest toward the
  // viewer (d points to the viewer), on the sphere and on the ray. From a point 1 cm outside (a
  // facet that keeps the sphere's area bulges out) it is the same entry point.
  const hr::Vec3 c(1, 2, 3);
  const hr::CurvedSurface s = only(sphere(c, 0.5));
  const hr::Vec3 toViewer = glm::normalize(hr::Vec3(1, 0.2, 0.6));
  const hr::Vec3 entry = c + 0.5 * glm::normalize(hr::Vec3(1, 0.1, 0.05));
  EXPECT_GT(glm::dot(toViewer, entry - c), 0.0);
  for (double off : {-0.01, 0.01}) {
    const hr::Vec3 p = entry + off * toViewer, q = s.meet(p, toViewer);
    EXPECT_NEAR(glm::length(q - c), 0.5, 1e-12);
    EXPECT_LT(glm::length(glm::cross(q - p, toViewer)), 1e-12);
    EXPECT_LT(glm::length(q - entry), 1e-9) << "the entry point, not the far side, from " << off;
  }
  // A line that misses the sphere leaves the point where it was; so does a flat primitive.
  const hr::Vec3 far(c + hr::Vec3(0, 0, 2));
  EXPECT_EQ(s.meet(far, hr::Vec3(1, 0, 0)), far);
  hr::Object quad;
  quad.type = hr::PrimitiveType::Quad;
  EXPECT_EQ(only(quad).meet(entry, toViewer), entry);
  // A cylinder of radius 1 along +z, seen from outside along -x in the plane z = 0.5: from a point
  // just inside its side the viewer's ray meets the side at radius 1, at the same height.
  hr::Object cyl;
  cyl.type = hr::PrimitiveType::Cylinder;
  cyl.base = {0, 0, 0}, cyl.axis = {0, 0, 1}, cyl.radius = 1.0, cyl.radius2 = 1.0, cyl.height = 2.0;
  const hr::Vec3 m = only(cyl).meet({0.98, 0.0, 0.5}, glm::normalize(hr::Vec3(1, 0.1, 0)));
  EXPECT_NEAR(std::hypot(m.x, m.y), 1.0, 1e-12);
  EXPECT_NEAR(m.z, 0.5, 1e-12);
  EXPECT_GT(m.x, 0.98);
}

/// The shiny sphere in 16 segments (object 0), its facets refined near the lamp: the BRIGHT-like
/// host's solution.
const hr::Solution& tessellatedSphere() {
  static const hr::Solution solved = [] {
    const std::string scene = testutil::shinySphereScene(R"({ "tessellation": 16 })");
    hr::SolverOptions o = hr::SolverOptions::from(hr::parseScene(scene, "").settings);
    o.eps = 2e-4;
    o.maxLevel = 5;
    auto s = testutil::solveText(scene, o);
    return hr::makeSolution(s.scene, *s.h, s.solver->radiosity());
  }();
  return solved;
}

TEST(CurvedSurface, TheDisplayShadesTessellatedFacetsAtTheSpheresOwnNormal) {
  // The facets' display vertices lie on the sphere (at its tessellation's vertices) or inside it (a
  // refined facet's inner corners, on the flat facet); the sphere's normal there is the radial
  // direction. Without the section the display estimates a vertex's normal from the facets meeting
  // there, and a refined facet's inner vertices meet only coplanar leaves: flat, its own normal.
  const hr::Solution& sol = tessellatedSphere();
  ASSERT_EQ(sol.surfaces.size(), 3u);
  ASSERT_EQ(sol.surfaces[0].kind, hr::CurvedKind::Sphere);
  std::size_t corners = 0, refined = 0;
  for (const hr::SolutionElement& e : sol.elements) refined += sol.patches[e.patch].object == 0 && e.level > 0 && e.leaf() ? 1 : 0;
  ASSERT_GT(refined, 0u) << "some facets must be refined for the inner vertices to be tested";
  const double exact = testutil::worstShadingDegrees(sol, corners);
  hr::Solution estimated = sol;
  estimated.surfaces.clear();
  std::size_t again = 0;
  const double estimate = testutil::worstShadingDegrees(estimated, again);
  std::printf("%zu sphere leaf corners (%zu leaves below a facet): shading normals %.2e degrees from the sphere's; %.2f with the estimate\n",
              corners, refined, exact, estimate);
  EXPECT_LT(exact, 1e-4) << "degrees";
  EXPECT_GT(estimate, 5.0) << "the estimate leaves refined facets flat inside (else the test shows nothing)";
}

TEST(CurvedSurface, ADamagedSurfacesSectionIsRefused) {
  const hr::Solution& sol = tessellatedSphere();
  const std::string good = *hr::findSection(sol, hr::kSurfaces);
  auto refused = [&](const std::string& bytes) {
    hr::Solution s = sol;
    hr::setSection(s, hr::kSurfaces, bytes);
    try {
      hr::reconstruct(s);
    } catch (const hr::InputError& e) {
      return std::string(e.what()).find("\"surfaces\"") != std::string::npos;
    }
    return false;
  };
  const std::size_t head = std::strlen(hr::kSurfaces), sphereAt = head + 4 + 1;  // the count, then object 0's kind
  EXPECT_FALSE(refused(good));
  EXPECT_TRUE(refused(good.substr(0, good.size() - 1))) << "truncated";
  EXPECT_TRUE(refused(good + std::string(1, '\0'))) << "trailing bytes";
  std::string foreign = good;
  foreign[0] = 'X';
  EXPECT_TRUE(refused(foreign)) << "without its name";
  std::string count = good;
  count[head] = 2;
  EXPECT_TRUE(refused(count)) << "entries for another number of objects";
  std::string kind = good;
  kind[head + 4] = 7;
  EXPECT_TRUE(refused(kind)) << "an unknown kind";
  auto withDouble = [&](std::size_t at, double x) {
    std::string b = good;
    std::memcpy(b.data() + at, &x, sizeof x);
    return b;
  };
  EXPECT_TRUE(refused(withDouble(sphereAt, std::nan("")))) << "not finite";
  std::string singular = good;
  for (int k = 0; k < 12; ++k) singular = std::string(singular).replace(sphereAt + 8 * std::size_t(k), 8, std::string(8, '\0'));
  EXPECT_TRUE(refused(singular)) << "a frame that cannot be inverted";
  EXPECT_TRUE(refused(withDouble(sphereAt + 16 * 8, -0.5))) << "a negative radius";
}

}  // namespace
