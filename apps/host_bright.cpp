// `--host bright`: the tessellating host in base_radiosity, with the extension (if any) through its
// hooks.
#include <hr/camera.h>
#include <hr/geometry.h>
#include <hr/hierarchy.h>
#include <hr/visibility.h>

#include <cstdio>

#include "host_front.h"

HostResult solveBright(HostJob& job) {
  job.progress.phase("tessellating");
  hr::TessellationReport rep;
  std::vector<hr::Patch> patches = hr::buildPatches(job.scene, rep);
  if (rep.droppedZeroArea) std::fprintf(stderr, "warning: dropped %zu zero-area face(s)\n", rep.droppedZeroArea);
  if (rep.splitNonPlanar) std::fprintf(stderr, "warning: split %zu non-planar quad(s) into triangles\n", rep.splitNonPlanar);
  hr::Hierarchy hier(std::move(patches));
  dropUnneededExtension(job);  // after tessellation: mesh files add their materials
  if (job.scene.cameras.empty()) job.scene.cameras.push_back(hr::autoCamera(hier.bounds()));
  job.ready();
  job.progress.phase("building visibility");
  hr::Visibility vis(hier.patches());
  hr::Solver solver(job.scene, hier, vis, job.opt, job.ext.get(), &job.progress);
  HostResult r;
  r.st = solver.solve();
  job.progress.phase("writing outputs");
  r.sol = hr::makeSolution(job.scene, hier, solver.radiosity());
  return r;
}
