// Glossy transport end to end, host and extension together (--algorithm is): the spots a glossy
// reflector throws on a wall against an independent integration of the optics, energy with glossy
// surfaces, a diffuse scene's bits unchanged by the extension, saved solutions that render from any
// camera like a fresh solve, hard cases, and thread independence.
#include <gtest/gtest.h>
#include <hr/rng.h>
#include <hr/solution_view.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "helpers.h"
#include "registry.h"
#include "test_dir.h"

namespace {

std::string readFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::unique_ptr<hr::Extension> makeIs(const std::vector<hr::OptionValue>& options = {}) {
  auto ext = adapters::findExtension("is").make();
  ext->configure(options);
  return ext;
}

/// The light an object receives: per-channel power (W) and its centroid (m), from a glossy solve.
struct Spot {
  hr::Rgb power{0.0};
  hr::Vec3 centroid[3];
};

Spot receivedBy(const testutil::Solved& run, std::uint32_t object) {
  Spot s;
  hr::Vec3 moment[3] = {hr::Vec3(0.0), hr::Vec3(0.0), hr::Vec3(0.0)};
  for (std::size_t i = 0; i < run.h->elements().size(); ++i) {
    const auto& e = run.h->element(static_cast<std::uint32_t>(i));
    if (!e.leaf() || run.h->patches()[e.patch].object != object) continue;
    hr::Rgb p = e.area * run.solver->irradiance()[i];
    s.power += p;
    for (int c = 0; c < 3; ++c) moment[c] += p[c] * e.center;
  }
  for (int c = 0; c < 3; ++c) s.centroid[c] = moment[c] / s.power[c];
  return s;
}

/// The same, integrated from the optics alone: every light sends L_e from its disk to the
/// reflector (a grid of points over both), the reflector's specular lobe f_s = rho_s (n+2)/(2 pi)
/// cos^n(alpha) sends it on (directions drawn from the lobe, weight rho_s (n+2)/(n+1) cos theta_o),
/// and what reaches the wall plane is summed. One bounce, no solver involved.
Spot spotFromOptics(const hr::Scene& sc, std::uint32_t reflector, double wallZ) {
  const hr::Object& r = sc.objects[reflector];
  const hr::Material& m = sc.materials[sc.materialIndex.at(r.material)];
  const hr::Vec3 a = r.quad[0], b = r.quad[1], d = r.quad[3];
  const hr::Vec3 ea = b - a, eb = d - a, nr = glm::normalize(glm::cross(ea, eb));
  const double areaR = glm::length(glm::cross(ea, eb));
  Spot s;
  hr::Vec3 moment[3] = {hr::Vec3(0.0), hr::Vec3(0.0), hr::Vec3(0.0)};
  hr::Rng rng(7, 1);
  const int NR = 24, NL = 4, NO = 64;
  // The lights as the scene tessellates them (a 16-sided disk holds 2.6 % less area than a circle).
  hr::Scene copy = sc;
  hr::TessellationReport rep;
  const std::vector<hr::Patch> patches = hr::buildPatches(copy, rep);
  for (const hr::Patch& light : patches) {
    const hr::Material& lm = sc.materials[light.material];
    if (!lm.emitter()) continue;
    const hr::Vec3 nl = light.normal;
    const double areaL = light.area;
    for (int i = 0; i < NR * NR; ++i) {
      hr::Vec3 y = a + ea * ((i % NR + rng.uniform()) / NR) + eb * ((i / NR + rng.uniform()) / NR);
      for (int j = 0; j < NL; ++j) {
        hr::Vec3 z = light.poly.sample((j + rng.uniform()) / NL, rng.uniform());
        hr::Vec3 wi = z - y;
        double dist2 = glm::dot(wi, wi);
        wi /= std::sqrt(dist2);
        double ci = glm::dot(nr, wi), cz = -glm::dot(nl, wi);
        if (ci <= 0.0 || cz <= 0.0) continue;
        // Irradiance at y from this bit of the light, times y's share of the reflector's area, W/m^2 * m^2.
        hr::Rgb dPhi = lm.emission * (ci * cz / dist2) * (areaL / NL) * (areaR / (NR * NR));
        const hr::Vec3 mir = 2.0 * glm::dot(nr, wi) * nr - wi;
        hr::Vec3 mu, mv;
        hr::Vec3 t = std::abs(mir.x) > 0.9 ? hr::Vec3(0, 1, 0) : hr::Vec3(1, 0, 0);
        mu = glm::normalize(glm::cross(t, mir)), mv = glm::cross(mir, mu);
        for (int k = 0; k < NO; ++k) {
          double cosA = std::pow(rng.uniform(), 1.0 / (m.exponent + 1.0)), sinA = std::sqrt(1.0 - cosA * cosA);
          double ph = 2.0 * hr::kPi * rng.uniform();
          hr::Vec3 wo = cosA * mir + sinA * (std::cos(ph) * mu + std::sin(ph) * mv);
          double co = glm::dot(nr, wo);
          if (co <= 0.0) continue;
          if (wo.z >= 0.0) continue;
          double tt = (wallZ - y.z) / wo.z;
          hr::Vec3 h = y + tt * wo;
          if (std::abs(h.x) > 3.0 || h.y < 0.0 || h.y > 3.0) continue;
          hr::Rgb p = dPhi * m.specular * ((m.exponent + 2.0) / (m.exponent + 1.0) * co / NO);
          s.power += p;
          for (int c = 0; c < 3; ++c) moment[c] += p[c] * h;
        }
      }
    }
  }
  for (int c = 0; c < 3; ++c) s.centroid[c] = moment[c] / s.power[c];
  return s;
}

TEST(GlossyTransport, ThreeLightsSpotsLandWhereTheOpticsPutThem) {
  // The three-lights scene with a black floor and a reflector without a diffuse part: all the wall
  // receives is then what the reflector's lobe throws on it (the lights face away from the wall), one
  // bounce, which the optics integrate without the solver.
  std::string json = readFile(std::string(GHR_SOURCE_DIR) + "/scenes/three_lights.json");
  auto blacken = [&](const std::string& mat, const std::string& from) {
    auto at = json.find("\"" + mat + "\"");
    ASSERT_NE(at, std::string::npos);
    at = json.find(from, at);
    ASSERT_NE(at, std::string::npos);
    json.replace(at, from.size(), "\"diffuse\": [0, 0, 0]");
  };
  blacken("floor", "\"diffuse\": [\n    0.4,\n    0.4,\n    0.4\n   ]");
  blacken("reflector", "\"diffuse\": [\n    0.05,\n    0.05,\n    0.05\n   ]");
  hr::Scene sc = hr::parseScene(json, "three_lights.json");
  hr::SolverOptions o = hr::SolverOptions::from(sc.settings);
  auto ext = makeIs();
  auto run = testutil::solveText(json, o, ext.get());
  Spot got = receivedBy(run, 1), want = spotFromOptics(sc, 2, -3.0);
  std::printf("spot power (W, RGB) %.4g %.4g %.4g, optics %.4g %.4g %.4g; centroid offsets (cm) %.2f %.2f %.2f\n",
              got.power.x, got.power.y, got.power.z, want.power.x, want.power.y, want.power.z,
              100 * glm::length(got.centroid[0] - want.centroid[0]), 100 * glm::length(got.centroid[1] - want.centroid[1]),
              100 * glm::length(got.centroid[2] - want.centroid[2]));
  for (int c = 0; c < 3; ++c) {
    SCOPED_TRACE("channel " + std::to_string(c));
    EXPECT_NEAR(got.power[c] / want.power[c], 1.0, 0.05) << "spot power " << got.power[c] << " W vs " << want.power[c];
    EXPECT_LT(glm::length(got.centroid[c] - want.centroid[c]), 0.02)
        << "centroid (" << got.centroid[c].x << ", " << got.centroid[c].y << ") vs (" << want.centroid[c].x << ", "
        << want.centroid[c].y << ")";
  }
}

}  // namespace
