// Parallel scaling of the solver and the reference tracer, in one run: the Soda Shoppe (straight from
// its MGF file), the Cornell box at a fine threshold and the three-lights scene with the glossy
// extension (Illumination Samples, its own settings) are solved, and the Cornell box path-traced at
// 256 spp, with 1, 2, 4, ... threads up to the machine's cores. Per phase: wall time, speedup over
// one thread, parallel efficiency and CPU time / wall time (CPU of the whole process while the phase
// ran). Each run is a forked child, so that thread pools and memory start fresh.
//   bench_scaling [SOURCE_DIR] [--quick]   (--quick: Cornell at 2e-4, three lights and 32 spp only)
#include <hr/output.h>
#include <hr/solution.h>
#include <hr/solver.h>
#include <ref/path_tracer.h>
#include <tbb/global_control.h>
#include <sys/resource.h>
#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "bench_common.h"
#include "registry.h"

namespace {

// "display": the solution reconstructed for display and every camera rendered, after the solve;
// "total" is the solve's.
constexpr int kPhases = 7;
const char* kPhaseNames[kPhases] = {"visibility", "refine", "gather", "push_pull", "energy", "display", "total"};

struct Row {
  double wall[kPhases] = {}, cpu[kPhases] = {};
  double peakRssMB = 0, cpuSeconds = 0;
  double solvePeakMB = 0;  // peak RSS when the solve ended, before the display phase
  bool ok = false;
};

double cpuNow() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// eps <= 0: the scene's own; algorithm: an extension from the table, or empty for the core alone.
Row solveRun(const std::string& scene, double eps, int threads, const std::string& algorithm) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  hr::Scene sc = scene.empty() ? hr::defaultScene() : hr::loadScene(scene);
  hr::TessellationReport rep;
  hr::Hierarchy h(hr::buildPatches(sc, rep));
  hr::Visibility vis(h.patches());
  hr::SolverOptions o = hr::SolverOptions::from(sc.settings);
  if (eps > 0.0) o.eps = eps;
  auto ext = algorithm.empty() ? nullptr : adapters::findExtension(algorithm).make();
  double c0 = cpuNow();
  hr::Solver solver(sc, h, vis, o, ext.get());
  hr::SolveStats st = solver.solve();
  Row r;
  const hr::PhaseStat* ph[5] = {&st.visibility, &st.refine, &st.gather, &st.pushPull, &st.energy};
  for (int i = 0; i < 5; ++i) r.wall[i] = ph[i]->wall, r.cpu[i] = ph[i]->cpu;
  r.wall[6] = st.tTotal;
  r.cpu[6] = cpuNow() - c0;
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  r.solvePeakMB = double(ru.ru_maxrss) / 1024.0;
  const double d0 = cpuNow();
  const auto w0 = std::chrono::steady_clock::now();
  hr::Solution sol = hr::makeSolution(sc, h, solver.radiosity());
  for (const hr::Camera& cam : sol.cameras) (void)hr::render(sol, cam, ext.get());
  r.wall[5] = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  r.cpu[5] = cpuNow() - d0;
  r.ok = true;
  return r;
}

Row traceRun(int spp, int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  hr::Scene sc = hr::defaultScene();
  hr::TessellationReport rep;
  ref::PathTracer pt(sc, hr::buildPatches(sc, rep));
  ref::Options o;
  o.spp = spp;
  double c0 = cpuNow();
  auto w0 = std::chrono::steady_clock::now();
  for (const hr::Camera& cam : sc.cameras) pt.render(cam, o);
  Row r;
  r.wall[6] = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  r.cpu[6] = cpuNow() - c0;
  r.ok = true;
  return r;
}

void table(const char* title, const std::vector<int>& threads, const std::vector<Row>& rows, bool phases) {
  std::printf("\n%s\n%-11s %7s %9s %8s %8s %8s %8s %9s\n", title, "phase", "threads", "wall_s", "speedup", "effic.", "cpu/wall",
              "peak_MB", "solve_MB");
  for (int p = phases ? 0 : kPhases - 1; p < kPhases; ++p)
    for (std::size_t i = 0; i < threads.size(); ++i) {
      const Row& r = rows[i];
      if (!r.ok) {
        std::printf("%-11s %7d   failed\n", kPhaseNames[p], threads[i]);
        continue;
      }
      double speedup = rows[0].wall[p] / std::max(r.wall[p], 1e-12);
      std::printf("%-11s %7d %9.3f %8.2f %8.2f %8.2f", kPhaseNames[p], threads[i], r.wall[p], speedup,
                  speedup / threads[i], r.cpu[p] / std::max(r.wall[p], 1e-12));
      // Peak resident memory of the whole run (solve and display) and of the solve alone, on the
      // total's line: the display could hide a rise in the solve's own peak.
      if (p == kPhases - 1) {
        std::printf(" %8.1f", r.peakRssMB);
        if (r.solvePeakMB > 0.0) std::printf(" %9.1f", r.solvePeakMB);  // the tracer has no solve
      }
      std::printf("\n");
    }
}

}  // namespace

int main(int argc, char** argv) {
  std::string src = GHR_SOURCE_DIR;
  bool quick = false;
  bench::sourceAndQuick(argc, argv, src, quick);
  int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<int> threads = {1};
  for (int t = 2; t <= std::max(2, cores); t *= 2) threads.push_back(t);
  if (threads.back() != cores && cores > 2) threads.push_back(cores);
  std::printf("bench_scaling: %d hardware threads; runs with", cores);
  for (int t : threads) std::printf(" %d", t);
  std::printf(" threads\n");

  struct Job {
    std::string title, scene;
    double eps;
    std::string algorithm;
  };
  std::vector<Job> jobs;
  if (!quick)
    jobs.push_back({"solve: Soda Shoppe (scenes/mgf/soda.mgf), eps 2e-4", src + "/scenes/mgf/soda.mgf", 2e-4, ""});
  jobs.push_back(
      {quick ? "solve: Cornell box, eps 2e-4" : "solve: Cornell box, eps 5e-5", "", quick ? 2e-4 : 5e-5, ""});
  jobs.push_back({"solve: three lights, glossy (--algorithm is), its own settings",
                  src + "/scenes/three_lights.json", 0.0, "is"});
  for (const Job& j : jobs) {
    std::vector<Row> rows;
    for (int t : threads)
      rows.push_back(bench::forked<Row>([&] { return solveRun(j.scene, j.eps, t, j.algorithm); }));
    table(j.title.c_str(), threads, rows, true);
  }
  const int spp = quick ? 32 : 256;
  std::vector<Row> rows;
  for (int t : threads) rows.push_back(bench::forked<Row>([&] { return traceRun(spp, t); }));
  table(("reference: Cornell box, " + std::to_string(spp) + " spp").c_str(), threads, rows, false);
  return 0;
}
