// What glossy transport costs and what it buys, in one run (issue 11):
// - on the three-lights scene and the glossy Cornell box: the diffuse core alone and Illumination
//   Samples with each directional basis (Haar, tetrahedron, SH), then Haar at finer spatial (--eps)
//   and directional (--dir-eps) thresholds: time by phase, peak RSS (each solve in its own forked
//   process), links, the extension's coefficients and samples, and the image's relative RMSE and
//   mean ratio against a path-traced reference of the same camera (light sources left out);
// - the built-in diffuse scene with --algorithm is against the core alone, interleaved runs, the
//   smallest time of each: what the extension costs a scene that has nothing glossy.
//   bench_glossy [SOURCE_DIR] [--ref-spp N] [--quick]
#include <hr/output.h>
#include <hr/solver.h>
#include <ref/compare.h>
#include <ref/path_tracer.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bench_common.h"
#include "registry.h"

namespace {

struct Config {
  const char* label;
  const char* algorithm;
  std::vector<hr::OptionValue> options;
  double epsScale = 1.0;
};

struct Row {
  double total = 0, visibility = 0, refine = 0, gather = 0, pushPull = 0, energy = 0;
  double links = 0, coefficients = 0, peakCoefficients = 0, samplesPeak = 0, samplesTotal = 0, reflectS = 0;
  double relRmse = 0, meanRatio = 0, imbalance = 0, peakRssMB = 0, cpuSeconds = 0;
  bool ok = false;
};

using bench::readFile;
using bench::stat;

Row solveAndCompare(const std::string& json, const Config& c, const hr::Image& reference) {
  hr::Scene sc = hr::parseScene(json, "bench");
  hr::TessellationReport rep;
  hr::Hierarchy h(hr::buildPatches(sc, rep));
  hr::Visibility vis(h.patches());
  hr::SolverOptions o = hr::SolverOptions::from(sc.settings);
  o.eps *= c.epsScale;
  std::unique_ptr<hr::Extension> ext;
  if (std::strcmp(c.algorithm, "diffuse") != 0) {
    ext = adapters::findExtension(c.algorithm).make();
    ext->configure(c.options);
  }
  hr::Solver solver(sc, h, vis, o, ext.get());
  hr::SolveStats st = solver.solve();
  Row r;
  r.total = st.tTotal, r.visibility = st.visibility.wall, r.refine = st.refine.wall, r.gather = st.gather.wall;
  r.pushPull = st.pushPull.wall, r.energy = st.energy.wall, r.links = double(st.links);
  r.imbalance = (st.emittedW.y - st.absorbedW.y - st.escapedW.y) / st.emittedW.y;
  if (ext) {
    auto s = ext->stats();
    r.coefficients = stat(s, "coefficients_total"), r.peakCoefficients = stat(s, "coefficients_peak_per_distribution");
    r.samplesPeak = stat(s, "samples_peak_per_reflect"), r.samplesTotal = stat(s, "samples_received_total");
    r.reflectS = stat(s, "reflect_cpu_seconds_summed_over_threads");
  }
  hr::Solution sol = hr::makeSolution(sc, h, solver.radiosity());
  hr::Image img = hr::render(sol, sc.cameras.front(), ext.get());
  ref::Metrics m = ref::compare(img, reference, -1, "solve", "reference", hr::emitterObjects(sc));
  r.relRmse = m.relRmse, r.meanRatio = m.meanRatio;
  r.ok = true;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::string src = GHR_SOURCE_DIR;
  int refSpp = 1024;
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0)
      quick = true;
    else if (std::strcmp(argv[i], "--ref-spp") == 0 && i + 1 < argc)
      refSpp = std::atoi(argv[++i]);
    else
      src = argv[i];
  }
  if (quick) refSpp = std::min(refSpp, 64);
  std::vector<Config> configs = {
      {"diffuse core", "diffuse", {}},
      {"is haar", "is", {}},
      {"is tetra", "is", {{"basis", "tetra"}}},
      {"is sh", "is", {{"basis", "sh"}}},
      {"is haar eps/2", "is", {}, 0.5},
      {"is haar eps/4", "is", {}, 0.25},
      {"is haar dir-eps 0.25", "is", {{"dir-eps", "0.25"}}},
      {"is haar dir-eps 0.1 max 5", "is", {{"dir-eps", "0.1"}, {"dir-max-level", "5"}}},
  };
  if (quick) configs.resize(2);
  for (const char* name : {"three_lights", "glossy_cornell"}) {
    const std::string json = readFile(src + "/scenes/" + name + ".json");
    hr::Scene sc = hr::parseScene(json, name);
    hr::TessellationReport rep;
    ref::PathTracer pt(sc, hr::buildPatches(sc, rep));
    ref::Options ro;
    ro.spp = refSpp;
    ref::CameraResult reference = pt.render(sc.cameras.front(), ro);
    std::printf("\n%s: reference %d spp (rel. std error of its mean %.2g %%); lights left out of the comparison\n", name,
                reference.spp, 100.0 * reference.relStdError);
    std::printf("%-26s %7s %6s %6s %6s %7s %6s %7s %8s %8s %6s %9s %7s %7s %7s\n", "configuration", "time_s", "visib",
                "refine", "push", "audit", "reflct", "RSS_MB", "links", "coeffs", "peak", "samples", "relRMSE", "mean",
                "imbal%");
    Row base;
    for (const Config& c : configs) {
      Row r = bench::forked<Row>([&] { return solveAndCompare(json, c, reference.image); });
      if (!r.ok) {
        std::printf("%-26s failed\n", c.label);
        continue;
      }
      if (std::strcmp(c.algorithm, "diffuse") == 0) base = r;
      std::printf("%-26s %7.2f %6.2f %6.2f %6.2f %7.2f %6.2f %7.1f %8.0f %8.0f %6.0f %9.0f %7.4f %7.4f %7.2f\n", c.label,
                  r.total, r.visibility, r.refine, r.pushPull, r.energy, r.reflectS, r.peakRssMB, r.links, r.coefficients,
                  r.peakCoefficients, r.samplesTotal, r.relRmse, r.meanRatio, 100.0 * r.imbalance);
    }
  }
  // What the extension costs a scene with nothing glossy: interleaved, smallest of each.
  double best[2] = {1e30, 1e30};
  const int repeats = quick ? 1 : 3;
  const std::string cornell = hr::kDefaultSceneJson;
  hr::Image none;
  for (int k = 0; k < repeats; ++k)
    for (int a = 0; a < 2; ++a) {
      Config c{a ? "is" : "diffuse", a ? "is" : "diffuse", {}};
      Row r = bench::forked<Row>([&] {
        hr::Scene sc = hr::parseScene(cornell, "");
        hr::TessellationReport rep;
        hr::Hierarchy h(hr::buildPatches(sc, rep));
        hr::Visibility vis(h.patches());
        std::unique_ptr<hr::Extension> ext;
        if (a) {
          ext = adapters::findExtension("is").make();
          // As glossyhr solve does: an extension that simulates no material is not loaded.
          bool needed = false;
          for (const auto& m : sc.materials) needed = needed || ext->simulates({m.diffuse, m.specular, m.exponent, m.emission});
          if (!needed) ext.reset();
        }
        hr::Solver solver(sc, h, vis, hr::SolverOptions::from(sc.settings), ext.get());
        Row x;
        x.total = solver.solve().tTotal;
        x.ok = true;
        return x;
      });
      best[a] = std::min(best[a], r.total);
    }
  std::printf("\nbuilt-in diffuse scene, %d interleaved runs each: diffuse core %.3f s, --algorithm is %.3f s, ratio %.3f\n",
              repeats, best[0], best[1], best[1] / best[0]);
  return 0;
}
