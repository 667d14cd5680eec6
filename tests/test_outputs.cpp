// Outputs: the .vtp read back by VTK's own reader, the .ghrs round trip (and rejection of truncated
// or foreign files), images free of NaN/Inf, and robustness of scaled and touching geometry.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <filesystem>
#include <fstream>

#include "helpers.h"
#include "test_dir.h"

namespace fs = std::filesystem;

namespace {

hr::SolverOptions quick() { return testutil::options(1e-3, 4); }

TEST(Outputs, VtpReadsBackWithVtk) {
  auto s = testutil::solveText(hr::kDefaultSceneJson, quick());
  hr::Solution sol = hr::makeSolution(s.scene, *s.h, s.solver->radiosity());
  fs::path p = testutil::testDir() / "test.vtp";
  hr::writeVtp(sol, p.string());
  vtkNew<vtkXMLPolyDataReader> r;
  r->SetFileName(p.string().c_str());
  r->Update();
  vtkPolyData* pd = r->GetOutput();
  ASSERT_EQ(static_cast<std::size_t>(pd->GetNumberOfCells()), s.stats.leaves);
  for (const char* name : {"radiosity", "object_id", "level", "area"})
    EXPECT_NE(pd->GetCellData()->GetArray(name), nullptr) << name;
  ASSERT_NE(pd->GetPointData()->GetArray("radiosity"), nullptr);
  vtkDataArray* b = pd->GetCellData()->GetArray("radiosity");
  for (vtkIdType i = 0; i < b->GetNumberOfTuples(); ++i)
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(b->GetComponent(i, c)));
  fs::remove(p);
}

TEST(Outputs, SolutionFileRoundTripAndRejection) {
  auto s = testutil::solveText(hr::kDefaultSceneJson, quick());
  hr::Solution sol = hr::makeSolution(s.scene, *s.h, s.solver->radiosity());
  fs::path p = testutil::testDir() / "test.ghrs";
  hr::saveSolution(sol, p.string());
  hr::Solution back = hr::loadSolution(p.string());
  ASSERT_EQ(back.elements.size(), sol.elements.size());
  for (std::size_t i = 0; i < sol.elements.size(); ++i) ASSERT_EQ(back.elements[i].radiosity, sol.elements[i].radiosity);
  // A saved solution renders exactly like a fresh one.
  hr::Image a = hr::render(sol, sol.cameras[0]), b = hr::render(back, back.cameras[0]);
  EXPECT_EQ(a.rgb, b.rgb);
  for (float v : a.rgb) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
  // Truncated and foreign files are rejected with a message naming the file.
  std::string bytes;
  {
    std::ifstream in(p, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  fs::path t = testutil::testDir() / "trunc.ghrs";
  std::ofstream(t, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  try {
    hr::loadSolution(t.string());
    ADD_FAILURE() << "truncated file accepted";
  } catch (const hr::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  std::ofstream(t, std::ios::binary) << "P6\n1 1\n255\nabc";
  EXPECT_THROW(hr::loadSolution(t.string()), hr::InputError);
  fs::remove(p);
  fs::remove(t);
}

/// Everything finite: radiosity, irradiance, energy, and a rendered image.
void expectFinite(const testutil::Solved& s) {
  for (std::size_t i = 0; i < s.h->elements().size(); ++i) {
    ASSERT_TRUE(hr::allFinite(s.solver->radiosity()[i])) << "element " << i;
    ASSERT_TRUE(hr::allFinite(s.solver->irradiance()[i])) << "element " << i;
  }
  ASSERT_TRUE(hr::allFinite(s.stats.absorbedW) && hr::allFinite(s.stats.escapedW));
}

std::string scaled(double k) {
  auto f = [&](double v) { return std::to_string(v * k); };
  return R"({ "materials": { "l": { "emission": [1,1,1], "diffuse": [0.5,0.5,0.5] }, "w": { "diffuse": [0.7,0.7,0.7] } },
  "objects": [ { "type": "box", "material": "w", "min": [0,0,0], "max": [)" + f(1) + "," + f(1) + "," + f(1) + R"(], "facing": "inward" },
    { "type": "box", "material": "l", "min": [)" + f(0.2) + ",0," + f(0.2) + "], \"max\": [" + f(0.5) + "," + f(0.3) + "," + f(0.5) + R"(] } ] })";
}

TEST(Robustness, ScaledScenesGiveScaleFreeAnswers) {
  // Radiosity is scale-invariant: the same room at 1e-3, 1 and 1e3 metres gives the same B.
  auto a = testutil::solveText(scaled(1e-3), quick());
  auto b = testutil::solveText(scaled(1.0), quick());
  auto c = testutil::solveText(scaled(1e3), quick());
  expectFinite(a);
  expectFinite(b);
  expectFinite(c);
  EXPECT_NEAR(a.meanRadiosity(0).y / b.meanRadiosity(0).y, 1.0, 0.01);
  EXPECT_NEAR(c.meanRadiosity(0).y / b.meanRadiosity(0).y, 1.0, 0.01);
}

TEST(Robustness, TouchingCoplanarAndSliverGeometry) {
  // A box standing on the floor (coplanar contact), two coplanar quads sharing an edge, a sliver
  // triangle 1e-7 wide and a zero-area face in an OBJ file.
  fs::path obj = testutil::testDir() / "sliver.obj";
  std::ofstream(obj) << "v 0 0.5 0\nv 1 0.5 0\nv 0.5 0.5 1e-7\nv 0 0.7 0\nv 1 0.7 0\nv 2 0.7 0\n"
                        "f 1 2 3\nf 4 5 6\n";
  std::string scene = R"({ "materials": { "l": { "emission": [2,2,2] }, "w": { "diffuse": [0.6,0.6,0.6] } },
    "objects": [
      { "type": "quad", "material": "w", "vertices": [[0,0,0],[0,0,1],[1,0,1],[1,0,0]] },
      { "type": "quad", "material": "w", "vertices": [[1,0,0],[1,0,1],[2,0,1],[2,0,0]] },
      { "type": "box", "material": "w", "min": [0.3,0,0.3], "max": [0.6,0.3,0.6] },
      { "type": "mesh", "material": "w", "file": ")" + obj.string() + R"(" },
      { "type": "quad", "material": "l", "vertices": [[0.5,1,0.2],[1.5,1,0.2],[1.5,1,0.8],[0.5,1,0.8]], "transform": { "rotate_deg": [180,0,0], "translate": [0,2,1] } } ] })";
  hr::Scene sc = hr::parseScene(scene, "");
  hr::TessellationReport rep;
  auto patches = hr::buildPatches(sc, rep);
  EXPECT_EQ(rep.droppedZeroArea, 1u) << "the collinear OBJ face is dropped and counted";
  auto s = testutil::solveText(scene, quick());
  expectFinite(s);
  hr::Solution sol = hr::makeSolution(s.scene, *s.h, s.solver->radiosity());
  hr::Camera cam;
  cam.eye = {1, 1.5, 3};
  cam.lookAt = {1, 0, 0.5};
  hr::Image img = hr::render(sol, cam);
  for (float v : img.rgb) ASSERT_TRUE(std::isfinite(v));
  fs::remove(obj);
}

}  // namespace
