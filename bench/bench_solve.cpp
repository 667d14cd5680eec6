// Solve cost of the built-in default scene (the Cornell box) at three thresholds, measured in one
// run: wall time by phase, rays, links, elements, the solver's own memory accounting and the peak
// resident memory of the process. Each threshold runs in a forked child so that its peak memory is
// its own (a process's peak only grows). Ratios are against the default eps 2e-4.
#include <hr/output.h>
#include <hr/solver.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>

namespace {

struct Row {
  double eps = 0, total = 0, refine = 0, visibility = 0, gather = 0, imbalance = 0;
  double rays = 0, links = 0, elements = 0, linkBytes = 0, elementBytes = 0, baseRss = 0;
  int iterations = 0;
};

Row solveOnce(double eps) {
  hr::Scene sc = hr::defaultScene();
  hr::TessellationReport rep;
  hr::Hierarchy h(hr::buildPatches(sc, rep));
  hr::Visibility vis(h.patches());
  hr::SolverOptions o = hr::SolverOptions::from(sc.settings);
  o.eps = eps;
  Row r;
  r.eps = eps;
  r.baseRss = double(hr::peakRssBytes());
  hr::Solver solver(sc, h, vis, o);
  hr::SolveStats st = solver.solve();
  r.total = st.tTotal, r.refine = st.tRefine, r.visibility = st.tVisibility, r.gather = st.tGather;
  r.rays = double(st.rays), r.links = double(st.links), r.elements = double(st.elements);
  r.linkBytes = double(st.linkBytes), r.elementBytes = double(st.elementBytes);
  r.iterations = st.iterations;
  r.imbalance = (st.emittedW.y - st.absorbedW.y - st.escapedW.y) / st.emittedW.y;
  return r;
}

}  // namespace

int main() {
  const double eps[] = {1e-3, 2e-4, 5e-5};
  Row rows[3];
  double peak[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    int fd[2];
    if (pipe(fd) != 0) return 1;
    pid_t pid = fork();
    if (pid == 0) {
      close(fd[0]);
      Row r = solveOnce(eps[i]);
      ssize_t w = write(fd[1], &r, sizeof r);
      _exit(w == ssize_t(sizeof r) ? 0 : 1);
    }
    close(fd[1]);
    ssize_t got = read(fd[0], &rows[i], sizeof(Row));
    close(fd[0]);
    int status = 0;
    rusage ru{};
    wait4(pid, &status, 0, &ru);
    if (got != ssize_t(sizeof(Row)) || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      std::fprintf(stderr, "bench_solve: the run at eps %g failed\n", eps[i]);
      return 1;
    }
    peak[i] = double(ru.ru_maxrss) * 1024.0;
  }
  std::printf("default scene (Cornell box), solve at three thresholds; ratios against eps 2e-4\n");
  std::printf("%8s %8s %8s %8s %8s %6s %10s %9s %9s %10s %10s %10s %9s\n", "eps", "time_s", "refine", "visib.",
              "gather", "iters", "rays", "links", "elements", "links_MB", "elems_MB", "peakRSS_MB", "imbal.%");
  for (int i = 0; i < 3; ++i) {
    const Row& r = rows[i];
    std::printf("%8.0e %8.3f %8.3f %8.3f %8.3f %6d %10.0f %9.0f %9.0f %10.2f %10.2f %10.1f %9.2f\n", r.eps, r.total,
                r.refine, r.visibility, r.gather, r.iterations, r.rays, r.links, r.elements, r.linkBytes / 1e6,
                r.elementBytes / 1e6, peak[i] / 1e6, 100.0 * r.imbalance);
  }
  const Row& d = rows[1];
  for (int i = 0; i < 3; ++i)
    std::printf("eps %.0e: time x%.2f, rays x%.2f, links x%.2f, peak RSS x%.2f (RSS before solving %.1f MB)\n",
                rows[i].eps, rows[i].total / d.total, rows[i].rays / d.rays, rows[i].links / d.links, peak[i] / peak[1],
                rows[i].baseRss / 1e6);
  return 0;
}
