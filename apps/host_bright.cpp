// `--host bright`: the tessellating host in base_radiosity, with the extension (if any) through its
// hooks.
#include <hr/auto_camera.h>
#include <hr/geometry.h>
#include <hr/hierarchy.h>
#include <hr/visibility.h>

#include <cstdio>
#include <memory>

#include "host_front.h"

namespace {

/// What the extension's views point into, alive as long as the result is.
struct BrightRun {
  std::unique_ptr<hr::Hierarchy> hier;
  std::unique_ptr<hr::Visibility> vis;
  std::unique_ptr<hr::Solver> solver;
};

}  // namespace

HostResult solveBright(HostJob& job) {
  job.progress.phase("tessellating");
  hr::TessellationReport rep;
  std::vector<hr::Patch> patches = hr::buildPatches(job.scene, rep);
  if (rep.droppedZeroArea) std::fprintf(stderr, "warning: dropped %zu zero-area face(s)\n", rep.droppedZeroArea);
  if (rep.splitNonPlanar) std::fprintf(stderr, "warning: split %zu non-planar quad(s) into triangles\n", rep.splitNonPlanar);
  auto run = std::make_shared<BrightRun>();
  run->hier = std::make_unique<hr::Hierarchy>(std::move(patches));
  dropUnneededExtension(job);  // after tessellation: mesh files add their materials
  job.progress.phase("building visibility");
  run->vis = std::make_unique<hr::Visibility>(run->hier->patches());
  if (job.scene.cameras.empty()) job.scene.cameras.push_back(hr::autoCamera(job.scene, run->hier->patches(), *run->vis));
  job.ready();
  run->solver = std::make_unique<hr::Solver>(job.scene, *run->hier, *run->vis, job.opt, job.ext.get(), &job.progress);
  HostResult r;
  r.st = run->solver->solve();
  job.progress.phase("writing outputs");
  r.sol = hr::makeSolution(job.scene, *run->hier, run->solver->radiosity());
  r.keep = run;
  return r;
}
