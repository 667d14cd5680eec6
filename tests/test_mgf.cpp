// The MGF reader against hand-written files with known answers: areas, normals and centroids of every
// entity, transforms (nested, mirrored, arrays), includes, the material conversions; bad input
// table-driven (file, line and entity named); and the four classic scenes (the Soda Shoppe's counts).
#include <gtest/gtest.h>
#include <hr/geometry.h>
#include <hr/mgf.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "helpers.h"
#include "test_dir.h"

namespace fs = std::filesystem;

namespace {

using hr::Vec3;

struct Built {
  hr::Scene scene;
  std::vector<hr::Patch> patches;
  double area = 0.0;
  Vec3 centroid{0.0};  // area-weighted
  Vec3 areaVector{0.0};
};

/// Files go to the running test's own folder, removed when it ends (test_dir.h).
fs::path writeMgf(const std::string& name, const std::string& text) {
  fs::path p = testutil::testDir() / name;
  std::ofstream(p) << text;
  return p;
}

/// A light far away keeps every test scene valid (a scene needs an emitter); it is excluded from
/// the sums by material.
const std::string kLight = "m lamp =\n ed 100\nv l1 =\n p 100 0 0\nv l2 =\n p 100 1 0\nv l3 =\n p 100 0 1\nf l1 l2 l3\n";

Built build(const std::string& text, int tessellation = 16) {
  Built b;
  b.scene = hr::loadMgfScene(writeMgf("t.mgf", text + kLight).string());
  b.scene.settings.tessellation = tessellation;
  hr::TessellationReport rep;
  b.patches = hr::buildPatches(b.scene, rep);
  for (const auto& p : b.patches) {
    if (b.scene.materials[p.material].emitter()) continue;
    b.area += p.area;
    b.centroid += p.area * p.poly.centroid();
    b.areaVector += p.area * p.normal;
  }
  b.centroid /= b.area;
  return b;
}

const std::string kSquare = "m w =\n rd 0.5\nv a =\n p 0 0 0\nv b =\n p 1 0 0\nv c =\n p 1 1 0\nv d =\n p 0 1 0\n";

TEST(Mgf, FacesConvexNonConvexAndWithHoles) {
  Built sq = build(kSquare + "f a b c d\n");
  EXPECT_NEAR(sq.area, 1.0, 1e-12);
  EXPECT_NEAR(glm::length(sq.areaVector - Vec3(0, 0, 1)), 0.0, 1e-12) << "right-hand rule: +z";
  // An L: the 2x2 square without its (1..2, 1..2) corner.
  Built l = build("m w =\n rd 0.5\nv a =\n p 0 0 0\nv b =\n p 2 0 0\nv c =\n p 2 1 0\nv d =\n p 1 1 0\n"
                  "v e =\n p 1 2 0\nv f =\n p 0 2 0\nf a b c d e f\n");
  EXPECT_NEAR(l.area, 3.0, 1e-12);
  EXPECT_NEAR(l.centroid.x, 5.0 / 6.0, 1e-12);
  // A 3x3 square with a 1x1 hole, given as MGF's seam: outer, seam in, hole reversed, seam out.
  Built h = build("m w =\n rd 0.5\nv o1 =\n p 0 0 0\nv o2 =\n p 3 0 0\nv o3 =\n p 3 3 0\nv o4 =\n p 0 3 0\n"
                  "v h1 =\n p 1 1 0\nv h2 =\n p 2 1 0\nv h3 =\n p 2 2 0\nv h4 =\n p 1 2 0\n"
                  "f o1 o2 o3 o4 h4 h3 h2 h1 h4 o4\n");
  EXPECT_NEAR(h.area, 8.0, 1e-9);
  EXPECT_NEAR(glm::length(h.centroid - Vec3(1.5, 1.5, 0)), 0.0, 1e-9);
  EXPECT_NEAR(glm::length(h.areaVector), 8.0, 1e-9) << "every triangle faces +z";
}

TEST(Mgf, CurvedPrimitivesKeepTheirAreaAndFacing) {
  const double pi = hr::kPi;
  const std::string c = "m w =\n rd 0.5\nv c =\n p 1 2 3\n n 0 0 1\nv top =\n p 1 2 5\n";
  Built s = build(c + "sph c 2\n", 128);
  EXPECT_NEAR(s.area / (16.0 * pi), 1.0, 1e-9);
  EXPECT_NEAR(glm::length(s.centroid - Vec3(1, 2, 3)), 0.0, 1e-6);
  int outward = 0, inward = 0;
  for (const auto& p : s.patches)
    if (!s.scene.materials[p.material].emitter()) (glm::dot(p.normal, p.poly.centroid() - Vec3(1, 2, 3)) > 0 ? outward : inward)++;
  EXPECT_EQ(inward, 0);
  Built si = build(c + "sph c -2\n", 32);
  for (const auto& p : si.patches)
    if (!si.scene.materials[p.material].emitter()) {
      EXPECT_LT(glm::dot(p.normal, p.poly.centroid() - Vec3(1, 2, 3)), 0.0);
    }
  // Open tube r = 1 from c to top (length 2): lateral area 4 pi, normals away from the axis.
  Built cy = build(c + "cyl c 1 top\n", 256);
  EXPECT_NEAR(cy.area / (4.0 * pi), 1.0, 1e-9);
  for (const auto& p : cy.patches) {
    if (cy.scene.materials[p.material].emitter()) continue;
    Vec3 radial = p.poly.centroid() - Vec3(1, 2, p.poly.centroid().z);
    EXPECT_GT(glm::dot(p.normal, radial), 0.0);
  }
  Built cyi = build(c + "cyl c -1 top\n", 16);
  for (const auto& p : cyi.patches)
    if (!cyi.scene.materials[p.material].emitter()) {
      EXPECT_LT(glm::dot(p.normal, p.poly.centroid() - Vec3(1, 2, p.poly.centroid().z)), 0.0);
    }
  // Cone radius 1 at c to an apex at top: lateral area pi r sqrt(r^2 + h^2) = pi sqrt(5).
  Built co = build(c + "cone c 1 top 0\n", 256);
  EXPECT_NEAR(co.area / (pi * std::sqrt(5.0)), 1.0, 1e-9);
  EXPECT_NEAR(co.centroid.z, 3.0 + 2.0 / 3.0, 1e-3) << "a cone's lateral centroid lies at 1/3 of its height";
  // Ring 1..2 about +z: area 3 pi, facing +z.
  Built r = build(c + "ring c 1 2\n", 256);
  EXPECT_NEAR(r.area / (3.0 * pi), 1.0, 1e-9);
  EXPECT_NEAR(r.areaVector.z / r.area, 1.0, 1e-9);
  // Torus between radii 1 and 2: minor radius 0.5 about a major radius 1.5: area 4 pi^2 R r. The
  // reader tessellates it at load (16 x 8 quads by default) scaled to keep that area (inscribed, the
  // quads had 0.968 of it); at 8 segments (the reader's least) too.
  Built t = build(c + "torus c 1 2\n");
  EXPECT_NEAR(t.area / (4.0 * pi * pi * 1.5 * 0.5), 1.0, 1e-9);
  Built t8 = build(c + "torus c -0.2 -1.8\n", 8);
  EXPECT_NEAR(t8.area / (4.0 * pi * pi * 1.0 * 0.8), 1.0, 1e-9);
  // Prism: the unit square extruded 2 along +z: closed box of area 2 + 4 * 2.
  Built pr = build(kSquare + "prism a b c d 2\n");
  EXPECT_NEAR(pr.area, 10.0, 1e-12);
  EXPECT_NEAR(glm::length(pr.areaVector), 0.0, 1e-12) << "a closed surface's area vector vanishes";
  EXPECT_NEAR(glm::length(pr.centroid - Vec3(0.5, 0.5, 1.0)), 0.0, 1e-12);
}

TEST(Mgf, TransformsNestMirrorAndRepeat) {
  // Rotate 90 about z, scale 2, then move: in that order.
  Built t = build(kSquare + "xf -rz 90 -s 2 -t 5 0 0\nf a b c d\nxf\n");
  EXPECT_NEAR(t.area, 4.0, 1e-12);
  EXPECT_NEAR(glm::length(t.centroid - Vec3(4, 1, 0)), 0.0, 1e-12);
  // Nesting: the inner transform applies first.
  Built n = build(kSquare + "xf -t 0 0 7\nxf -s 3\nf a b c d\nxf\nxf\n");
  EXPECT_NEAR(glm::length(n.centroid - Vec3(1.5, 1.5, 7)), 0.0, 1e-12);
  // A mirror mirrors the facing too (a closed object mirrored stays outward-facing): the square at
  // z = 0 mirrored in z faces -z.
  Built m = build(kSquare + "xf -mz\nf a b c d\nxf\n");
  EXPECT_NEAR(m.areaVector.z, -1.0, 1e-12);
  Built box = build(kSquare + "xf -mx\nprism a b c d 1\nxf\n");
  EXPECT_NEAR(glm::length(box.areaVector), 0.0, 1e-12);
  for (const auto& p : box.patches)
    if (!box.scene.materials[p.material].emitter()) {
      EXPECT_GT(glm::dot(p.normal, p.poly.centroid() - box.centroid), 0.0);
    }
  // An array: four copies, each moved 2 further along y.
  Built a = build(kSquare + "xf -a 4 -t 0 2 0\nf a b c d\nxf\n");
  EXPECT_NEAR(a.area, 4.0, 1e-12);
  EXPECT_NEAR(a.centroid.y, 0.5 + 3.0, 1e-12);
  EXPECT_EQ(a.scene.entityCounts["mgf f"], 4u + 1u) << "four copies and the test light";
}

TEST(Mgf, IncludesAreRelativeAndTransformed) {
  writeMgf("part.mgf", kSquare + "f a b c d\n");
  Built b = build("i part.mgf -t 0 0 4\n");
  EXPECT_NEAR(glm::length(b.centroid - Vec3(0.5, 0.5, 4)), 0.0, 1e-12);
}

TEST(Mgf, MaterialConversions) {
  Built b = build("c\n cxy 0.3333333333 0.3333333333\nm grey =\n rd 0.5\n rs 0.3 0.1\nv a =\n p 0 0 0\nv b =\n p 1 0 0\n"
                  "v c =\n p 0 1 0\nf a b c\nm lit =\n ed 562.345\nf c b a\n"
                  "m glass =\n rd 0.05\n ts 0.9 0\nf a c b\nm mirror =\n rs 0.9 0\nf b a c\n"
                  "m hot =\n rd 0.9\n rs 0.2 0.05\nf b c a\n");
  const auto& mats = b.scene.materials;
  auto find = [&](const std::string& tail) {
    for (const auto& m : mats)
      if (m.name.size() >= tail.size() && m.name.compare(m.name.size() - tail.size(), tail.size(), tail) == 0) return m;
    ADD_FAILURE() << "no material " << tail;
    return hr::Material{};
  };
  hr::Material grey = find(":grey");
  EXPECT_NEAR(grey.diffuse.x, 0.5, 1e-6);
  EXPECT_NEAR(grey.diffuse.z, 0.5, 1e-6) << "MGF's neutral colour is grey";
  EXPECT_NEAR(grey.specular.y, 0.3, 1e-6);
  EXPECT_NEAR(grey.exponent, 198.0, 1e-9) << "n = 2 / alpha^2 - 2";
  // ed is luminous exitance (lm/m^2): L = ed / (179 lm/W) / pi.
  EXPECT_NEAR(find(":lit").emission.y, 562.345 / 179.0 / hr::kPi, 1e-9);
  EXPECT_EQ(find(":mirror").exponent, 10000.0);
  hr::Material hot = find(":hot");
  EXPECT_NEAR(hot.diffuse.x + hot.specular.x, 1.0, 1e-9) << "energy-gaining 1.1 scaled to 1";
  std::string all;
  for (const auto& d : b.scene.dropped) all += d + "\n";
  EXPECT_NE(all.find("transmission"), std::string::npos) << all;
  EXPECT_NE(all.find("glass"), std::string::npos) << all;
  EXPECT_NE(all.find("mirror"), std::string::npos) << all;
  EXPECT_NE(all.find("hot (1.1)"), std::string::npos) << all;
  // Spectra: a flat one is MGF's neutral white (x = y = 1/3, equal energy) to the fit's accuracy; one
  // concentrated at 600-620 nm is orange-red.
  Built flat = build("c\n cspec 400 700 1 1 1 1\nm w =\n rd 0.5\nv a =\n p 0 0 0\nv b =\n p 1 0 0\nv c =\n p 0 1 0\nf a b c\n");
  hr::Material fw = flat.scene.materials[flat.scene.materialIndex.at(flat.scene.materials[0].name)];
  // (The fit puts a flat 400-700 nm spectrum at x = 0.3334, y = 0.3341.)
  EXPECT_NEAR(fw.diffuse.x / fw.diffuse.y, 1.0, 0.02);
  EXPECT_NEAR(fw.diffuse.z / fw.diffuse.y, 1.0, 0.02);
  Built orange = build("c\n cspec 580 640 0 0 0 1 1 0 0\nm w =\n rd 0.5\nv a =\n p 0 0 0\nv b =\n p 1 0 0\nv c =\n p 0 1 0\nf a b c\n");
  hr::Material ow = orange.scene.materials[0];
  EXPECT_GT(ow.diffuse.x, 3.0 * ow.diffuse.z);
  // A saturated red: red channel above the others, luminance as given.
  hr::Rgb red = hr::cieToRgb(0.6, 0.33, 0.4);
  EXPECT_GT(red.x, red.y);
  EXPECT_GT(red.x, red.z);
}

struct BadMgf {
  const char* name;
  const char* text;
  const char* expect;
};
void PrintTo(const BadMgf& c, std::ostream* os) { *os << c.name; }

class MgfErrors : public ::testing::TestWithParam<BadMgf> {};

TEST_P(MgfErrors, NameFileLineAndEntity) {
  const BadMgf& c = GetParam();
  fs::path p = writeMgf(std::string(c.name) + ".mgf", c.text);
  try {
    hr::loadMgfScene(p.string());
    FAIL() << "accepted: " << c.name;
  } catch (const hr::InputError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find(p.string()), std::string::npos) << m;
    EXPECT_NE(m.find(c.expect), std::string::npos) << m;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Table, MgfErrors,
    ::testing::Values(
        BadMgf{"bad_number", "v a =\n p 1 x 3\n", "line 2: p: argument 2 \"x\" is not a finite number"},
        BadMgf{"undefined_vertex", "m w =\n rd .5\nf a b c\n", "line 3: f: undefined vertex \"a\""},
        BadMgf{"undefined_material", "m nope\n", "line 1: m: undefined material \"nope\""},
        BadMgf{"bad_arity", "v a =\n p 0 0 0\nsph a\n", "line 3: sph: expected 2 arguments, got 1"},
        BadMgf{"unknown_entity", "bogus 1 2\n", "line 1: bogus: unknown entity"},
        BadMgf{"opposite_radii", "v a =\nv b =\n p 0 0 1\ncone a 1 b -1\n", "line 4: cone: radii of opposite signs"},
        BadMgf{"ring_without_normal", "v a =\nring a 1 2\n", "line 2: ring: the centre vertex needs a normal"},
        BadMgf{"negative_reflectance", "m w =\n rd -0.2\n", "line 2: rd: must be in [0, 1]"},
        BadMgf{"unmatched_xf_end", "xf\n", "line 1: xf: xf end without a matching xf"},
        BadMgf{"open_array", "xf -a 2 -t 1 0 0\n", "line 1: xf: array without its closing xf"},
        BadMgf{"unclosed_xf", "xf -t 1 0 0\n", "end of file inside an xf context"},
        BadMgf{"missing_include", "i nothere.mgf\n", "line 1: i: cannot open included file"},
        BadMgf{"recursive_include", "i recursive_include.mgf\n", "recursive include"},
        BadMgf{"face_too_small", "v a =\nf a a\n", "line 2: f: a face needs at least 3 vertices"}),
    [](const auto& tp) { return std::string(tp.param.name); });

const std::string kScenes = std::string(GHR_SOURCE_DIR) + "/scenes/";

TEST(MgfScenes, AllFourClassicsLoadAndTheSodaShoppeCountsAgree) {
  for (const char* f : {"soda", "floor_gloss", "cube", "corridor"}) {
    hr::Scene s = hr::loadScene(kScenes + "mgf/" + f + ".mgf");
    hr::TessellationReport rep;
    EXPECT_FALSE(hr::buildPatches(s, rep).empty()) << f;
  }
  hr::Scene soda = hr::loadScene(kScenes + "mgf/soda.mgf");
  EXPECT_EQ(soda.entityCounts["mgf f"], 331u);
  EXPECT_EQ(soda.entityCounts["mgf cyl"], 575u);
  EXPECT_EQ(soda.entityCounts["mgf cone"], 461u);
  EXPECT_EQ(soda.entityCounts["mgf sph"], 274u);
  EXPECT_EQ(soda.entityCounts["mgf ring"], 70u);
}

TEST(MgfScenes, FloorGlossSolvesThroughItsJsonWrapper) {
  hr::Scene s = hr::loadScene(kScenes + "floor_gloss.json");
  ASSERT_EQ(s.cameras.size(), 1u);
  hr::TessellationReport rep;
  hr::Hierarchy h(hr::buildPatches(s, rep));
  hr::Visibility vis(h.patches());
  hr::Solver solver(s, h, vis, hr::SolverOptions::from(s.settings));
  hr::SolveStats st = solver.solve();
  EXPECT_TRUE(st.converged);
  EXPECT_NEAR((st.absorbedW.y + st.escapedW.y) / st.emittedW.y, 1.0, 0.01);
}

}  // namespace
