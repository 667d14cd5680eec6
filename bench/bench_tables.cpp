// The paper's Tables 2 and 3 as measured ratios, in one run (issue 13): Illumination Samples (IS)
// against the Radiance Clustering baseline (RC, immediate push), both gathering as the paper ran
// them, on the three-lights scene at (--dir-eps, --dir-min-level/--dir-max-level) = (0.5, 1/3),
// (0.1, 1/3), (0.5, 1/4), (0.5, 1/5) and on the glossy-sphere scene at (0.5, 1/3): basis
// coefficients at the end and at their peak, solve time (CPU seconds of a one-thread solve: the wall
// clock of a shared machine drifts by tens of percent between runs), peak RSS (each solve in its own forked
// process), BRDF evaluations and extension node visits (reflect + pull for IS; per-sample descents
// + pull for RC), the IS/RC ratios as the paper's "percent gain" (1 - IS/RC), and the image
// difference between the two (light sources left out). RC adds each reflected sample's projection into
// a leaf exactly (--rc-add exact, the paper's "added into this function"); a second table puts the same
// IS runs beside RC with --rc-add recut, which re-projects the running sum and holds fewer. Then IS
// shooting against IS gathering on the same scenes: time, push/pull share of it, and the most samples
// held in one pass/iteration.
// Last, the paper's Table 1 on the empty Soda Shoppe room (scenes/soda_room.json): RC with the
// non-adaptive tetrahedron basis against the adaptive Haar basis at (max) levels 3 and 4:
// distributions, coefficients (the paper's "triangles"), time, and the glossy floor's image error
// against a path-traced reference of the same camera.
//   bench_tables [SOURCE_DIR] [--quick | --table1 | --simple-soda | --without-soda]   (--quick: the
//   first three-lights row only, no Table 1; --table1: Table 1 alone; --simple-soda: the simple Soda
//   Shoppe's row alone, its longest, to be run apart; --without-soda: every other row, no Table 1)
#include <hr/output.h>
#include <hr/solver.h>
#include <ref/compare.h>
#include <ref/path_tracer.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_common.h"
#include "registry.h"

namespace {

struct Row {
  double seconds = 0, pushPullShare = 0, coefficients = 0, peakCoefficients = 0, brdf = 0, visits = 0;
  double samplesPeak = 0, imbalance = 0, distributions = 0, peakRssMB = 0, cpuSeconds = 0;
  bool ok = false;
};

struct Setting {
  const char* scene;
  const char* dirEps;
  const char* minLevel;
  const char* maxLevel;
  const char* basis = "haar";
};

/// Solves `scene` with an extension and writes its first camera's image to `image` (EXR).
/// rcAdd: RC's --rc-add (nullptr: its default, the exact sum).
Row solve(const std::string& src, const Setting& set, const char* algorithm, hr::Iteration it, const std::string& image,
          const char* rcAdd = nullptr) {
  // One thread: the CPU time of the child is then the solve's time, and other work on a shared
  // machine stretches the wall clock but not that (the ratios are taken from it).
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const std::string path = src + "/scenes/" + set.scene + ".json";
  hr::Scene sc = hr::parseScene(bench::readFile(path), path);
  hr::TessellationReport rep;
  hr::Hierarchy h(hr::buildPatches(sc, rep));
  hr::Visibility vis(h.patches());
  hr::SolverOptions o = hr::SolverOptions::from(sc.settings);
  o.iteration = it;
  o.maxIterations = 2000;
  auto ext = adapters::findExtension(algorithm).make();
  std::vector<hr::OptionValue> opts;
  if (std::strcmp(set.basis, "tetra") == 0)
    opts = {{"basis", "tetra"}, {"tetra-level", set.maxLevel}};
  else
    opts = {{"dir-eps", set.dirEps}, {"dir-min-level", set.minLevel}, {"dir-max-level", set.maxLevel}};
  if (rcAdd) opts.push_back({"rc-add", rcAdd});
  ext->configure(opts);
  hr::Solver solver(sc, h, vis, o, ext.get());
  timespec t0{}, t1{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t0);
  hr::SolveStats st = solver.solve();
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t1);
  auto s = ext->stats();
  Row r;
  r.seconds = double(t1.tv_sec - t0.tv_sec) + 1e-9 * double(t1.tv_nsec - t0.tv_nsec);  // CPU s of the solve
  r.pushPullShare = st.pushPull.cpu / std::max(1e-12, r.seconds);
  r.coefficients = bench::stat(s, "coefficients_total");
  r.distributions = bench::stat(s, "distributions");
  r.peakCoefficients = bench::stat(s, "coefficients_held_peak");
  r.brdf = bench::stat(s, "brdf_evaluations");
  r.visits = bench::stat(s, "reflect_leaf_visits") + bench::stat(s, "pull_node_visits") + bench::stat(s, "rc_descent_node_visits");
  r.samplesPeak = double(st.peakSamplesAtOnce);  // held for reflection at once (a shooting pass: one batch)
  r.imbalance = (st.emittedW.y - st.absorbedW.y - st.escapedW.y) / st.emittedW.y;
  hr::Solution sol = hr::makeSolution(sc, h, solver.radiosity());
  hr::writeExr(hr::render(sol, sc.cameras.front(), ext.get()), image);
  r.ok = true;
  return r;
}

/// Image relative RMSE of a against b, lights left out.
double imageDifference(const std::string& src, const Setting& set, const std::string& a, const std::string& b) {
  const std::string path = src + "/scenes/" + set.scene + ".json";
  hr::Scene sc = hr::parseScene(bench::readFile(path), path);
  return ref::compare(hr::readExr(a), hr::readExr(b), -1, a, b, hr::emitterObjects(sc)).relRmse;
}

/// The paper's Table 1: RC with the tetrahedron basis and with Haar at levels 3 and 4 on the empty
/// room, the glossy floor's image against a path-traced reference.
void table1(const std::string& src, const std::filesystem::path& dir) {
  const Setting room{"soda_room", "0.5", "1", "3"};
  const std::string path = src + "/scenes/soda_room.json";
  hr::Scene sc = hr::parseScene(bench::readFile(path), path);
  hr::TessellationReport rep;
  ref::PathTracer pt(sc, hr::buildPatches(sc, rep));
  ref::Options ro;
  ro.spp = 256;
  ref::CameraResult reference = pt.render(sc.cameras.front(), ro);
  const std::string refPath = (dir / "table1_reference.exr").string();
  hr::writeExr(reference.image, refPath);
  long floor = -1;  // the object holding the glossy floor tile
  for (std::uint32_t o = 0; o < sc.objects.size() && floor < 0; ++o)
    if (sc.objects[o].material.find("floor_tile") != std::string::npos) floor = long(o);
  std::printf("\nTable 1: empty Soda room, RC, non-adaptive tetrahedron vs adaptive Haar (reference %d spp, rel. std "
              "error %.2g %%; floor = object %ld)\n",
              reference.spp, 100.0 * reference.relStdError, floor);
  std::printf("%5s | %6s %6s | %9s %9s | %7s %7s | %8s %8s\n", "level", "distr", "", "tetra coef", "Haar coef", "tetra s",
              "Haar s", "tetra fl", "Haar fl");
  for (const char* level : {"3", "4"}) {
    Setting tetra = room, haar = room;
    tetra.basis = "tetra", tetra.maxLevel = level, haar.maxLevel = level;
    const std::string ti = (dir / (std::string("t1_tetra") + level + ".exr")).string(),
                      hi = (dir / (std::string("t1_haar") + level + ".exr")).string();
    Row t = bench::forked<Row>([&] { return solve(src, tetra, "rc", hr::Iteration::Gather, ti); });
    Row h = bench::forked<Row>([&] { return solve(src, haar, "rc", hr::Iteration::Gather, hi); });
    if (!t.ok || !h.ok) {
      std::printf("%5s failed\n", level);
      continue;
    }
    auto floorError = [&](const std::string& img) {
      return ref::compare(hr::readExr(img), hr::readExr(refPath), floor, img, refPath).relRmse;
    };
    std::printf("%5s | %6.0f %6.0f | %9.0f %9.0f | %7.2f %7.2f | %8.4f %8.4f\n", level, t.distributions, h.distributions,
                t.coefficients, h.coefficients, t.seconds, h.seconds, floorError(ti), floorError(hi));
  }
  std::printf("(distr: distributions held, tetra and Haar; fl: the floor's image rel. RMSE against the reference)\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::string src = GHR_SOURCE_DIR;
  bool quick = false;
  bench::sourceAndQuick(argc, argv, src, quick, {"--table1", "--simple-soda", "--without-soda"});
  bool onlyTable1 = false, onlySoda = false, noSoda = false;
  for (int i = 1; i < argc; ++i) {
    onlyTable1 = onlyTable1 || std::strcmp(argv[i], "--table1") == 0;
    onlySoda = onlySoda || std::strcmp(argv[i], "--simple-soda") == 0;
    noSoda = noSoda || std::strcmp(argv[i], "--without-soda") == 0;
  }
  if (int(quick) + int(onlyTable1) + int(onlySoda) + int(noSoda) > 1) {
    std::fprintf(stderr, "%s: --quick, --table1, --simple-soda and --without-soda each choose what runs; give one\n",
                 argv[0]);
    return 2;
  }
  std::vector<Setting> settings = {{"three_lights", "0.5", "1", "3"},
                                   {"three_lights", "0.1", "1", "3"},
                                   {"three_lights", "0.5", "1", "4"},
                                   {"three_lights", "0.5", "1", "5"},
                                   {"glossy_sphere", "0.5", "1", "3"},
                                   {"simple_soda", "0.5", "1", "3"}};
  if (quick) settings.resize(1);
  if (onlyTable1) settings.clear();
  if (onlySoda) settings.erase(settings.begin(), settings.end() - 1);
  if (noSoda) settings.pop_back();
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("bench_tables_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  auto image = [&](std::size_t k, const char* what) { return (dir / (std::to_string(k) + what + ".exr")).string(); };

  if (!settings.empty()) {  // --table1 alone prints only Table 1
    std::printf("Tables 2 and 3: IS vs RC, both gathering (coefficients: basis coefficients of all distributions;\n"
                "gain = 1 - IS/RC as the paper prints it; image: rel. RMSE of RC's image against IS's, lights left out)\n");
    std::printf("%-13s %4s %4s | %9s %9s %6s | %9s %9s %6s | %7s %7s %6s | %7s %7s | %7s %7s | %8s\n", "scene", "eps", "m/M",
                "IS coef", "RC coef", "gain", "IS peak", "RC peak", "gain", "IS s", "RC s", "gain", "IS MB", "RC MB",
                "BRDF", "visits", "image");
    std::vector<Row> gathered(settings.size()), recut(settings.size());
    // Issue 13's bars, over the rows of this run: IS/RC peak coefficients <= 0.63, time <= 0.73, images <= 2 %.
    double worstCoef = 0.0, worstTime = 0.0, worstImage = 0.0;
    std::size_t measured = 0;
    for (std::size_t k = 0; k < settings.size(); ++k) {
      const Setting& set = settings[k];
      Row is = bench::forked<Row>([&] { return solve(src, set, "is", hr::Iteration::Gather, image(k, "is")); });
      Row rc = bench::forked<Row>([&] { return solve(src, set, "rc", hr::Iteration::Gather, image(k, "rc")); });
      gathered[k] = is;
      // The compacting variant beside it (not the paper's RC; the simple soda's would double its row's time).
      if (std::strcmp(set.scene, "simple_soda") != 0)
        recut[k] = bench::forked<Row>(
            [&] { return solve(src, set, "rc", hr::Iteration::Gather, image(k, "rc_recut"), "recut"); });
      if (!is.ok || !rc.ok) {
        std::printf("%-13s %4s %s/%s failed\n", set.scene, set.dirEps, set.minLevel, set.maxLevel);
        continue;
      }
      const double imageDiff = imageDifference(src, set, image(k, "rc"), image(k, "is"));
      std::printf("%-13s %4s %s/%s  | %9.0f %9.0f %5.1f%% | %9.0f %9.0f %5.1f%% | %7.2f %7.2f %5.1f%% | %7.1f %7.1f | %7.3f %7.3f | %8.4f\n",
                  set.scene, set.dirEps, set.minLevel, set.maxLevel, is.coefficients, rc.coefficients,
                  100 * (1 - is.coefficients / rc.coefficients), is.peakCoefficients, rc.peakCoefficients,
                  100 * (1 - is.peakCoefficients / rc.peakCoefficients), is.seconds, rc.seconds,
                  100 * (1 - is.seconds / rc.seconds), is.peakRssMB, rc.peakRssMB, is.brdf / rc.brdf, is.visits / rc.visits,
                  imageDiff);
      worstCoef = std::max(worstCoef, is.peakCoefficients / rc.peakCoefficients);
      worstTime = std::max(worstTime, is.seconds / rc.seconds);
      worstImage = std::max(worstImage, imageDiff);
      ++measured;
    }
    if (measured > 0)
      std::printf("issue 13's bars over these %zu rows: IS/RC peak coefficients <= 0.63: %s (worst %.2f); time <= 0.73: "
                  "%s (worst %.2f); RC vs IS images <= 2 %%: %s (worst %.2f %%)\n",
                  measured, worstCoef <= 0.63 ? "met" : "MISSED", worstCoef, worstTime <= 0.73 ? "met" : "MISSED",
                  worstTime, worstImage <= 0.02 ? "met" : "MISSED", 100 * worstImage);
    std::printf("(BRDF and visits columns: IS/RC ratios; RC adds each sample's projection exactly, --rc-add exact)\n\n"
                "The same IS runs against RC with --rc-add recut (the running sum re-projected at every sample, as\n"
                "the pull sums: a compacting RC the paper did not run; not run on the simple soda)\n");
    std::printf("%-13s %4s %4s | %9s %9s %6s | %9s %9s %6s | %7s %7s %6s | %8s\n", "scene", "eps", "m/M", "IS coef",
                "RCr coef", "IS/RCr", "IS peak", "RCr peak", "IS/RCr", "IS s", "RCr s", "IS/RCr", "image");
    for (std::size_t k = 0; k < settings.size(); ++k) {
      const Setting& set = settings[k];
      const Row &is = gathered[k], &rc = recut[k];
      if (!is.ok || !rc.ok) continue;
      std::printf("%-13s %4s %s/%s  | %9.0f %9.0f %6.2f | %9.0f %9.0f %6.2f | %7.2f %7.2f %6.2f | %8.4f\n", set.scene,
                  set.dirEps, set.minLevel, set.maxLevel, is.coefficients, rc.coefficients, is.coefficients / rc.coefficients,
                  is.peakCoefficients, rc.peakCoefficients, is.peakCoefficients / rc.peakCoefficients, is.seconds,
                  rc.seconds, is.seconds / rc.seconds, imageDifference(src, set, image(k, "rc_recut"), image(k, "is")));
    }
    std::printf("\nIS shooting vs IS gathering\n");
    std::printf("%-13s %4s %4s | %7s %7s | %8s %8s | %9s %9s | %8s\n", "scene", "eps", "m/M", "gath s", "shoot s", "gath pp",
                "shoot pp", "gath smp", "shoot smp", "image");
    for (std::size_t k = 0; k < settings.size(); ++k) {
      const Setting& set = settings[k];
      if (k > 0 && std::strcmp(set.scene, settings[k - 1].scene) == 0 && std::strcmp(set.maxLevel, "3") != 0) continue;
      Row sh = bench::forked<Row>([&] { return solve(src, set, "is", hr::Iteration::Shoot, image(k, "shoot")); });
      const Row& g = gathered[k];
      if (!sh.ok || !g.ok) continue;
      std::printf("%-13s %4s %s/%s  | %7.2f %7.2f | %7.1f%% %7.1f%% | %9.0f %9.0f | %8.4f\n", set.scene, set.dirEps,
                  set.minLevel, set.maxLevel, g.seconds, sh.seconds, 100 * g.pushPullShare, 100 * sh.pushPullShare,
                  g.samplesPeak, sh.samplesPeak, imageDifference(src, set, image(k, "shoot"), image(k, "is")));
    }
  }
  if (!quick && !onlySoda && !noSoda) table1(src, dir);
  std::filesystem::remove_all(dir);
  return 0;
}
