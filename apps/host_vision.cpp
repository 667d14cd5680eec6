// `--host vision`: the VISION-like host in vision_host. It has no glossy adapter yet, so a scene
// that needs an extension is refused (exit 2) rather than solved without its glossy light.
#include <hr/camera.h>
#include <vision/solver.h>

#include <cstdio>

#include "host_front.h"

HostResult solveVision(HostJob& job) {
  job.progress.phase("building surfaces");
  vision::SurfaceReport rep;
  std::vector<vision::Surface> surfaces = vision::buildSurfaces(job.scene, rep);
  if (rep.dropped) std::fprintf(stderr, "warning: dropped %zu zero-area face(s)\n", rep.dropped);
  if (rep.nonPlanarQuads) std::fprintf(stderr, "warning: split %zu non-planar quad(s) into triangles\n", rep.nonPlanarQuads);
  if (rep.split) std::fprintf(stderr, "note: %zu extra surface(s) from polygons not star-shaped about their centroid\n", rep.split);
  dropUnneededExtension(job);
  if (job.ext)
    throw hr::InputError("--algorithm " + job.algorithm +
                         " with --host vision: the VISION-like host has no glossy adapter yet (adapters/vision); "
                         "use --host bright for glossy scenes");
  vision::Hierarchy hier(std::move(surfaces));
  if (job.scene.cameras.empty()) job.scene.cameras.push_back(hr::autoCamera(hier.bounds()));
  job.ready();
  job.progress.phase("building visibility");
  vision::CurvedVisibility vis(hier.surfaces());
  vision::Solver solver(job.scene, hier, vis, job.opt, &job.progress);
  HostResult r;
  r.st = solver.solve();
  r.st.iteration = hr::Iteration::Shoot;  // link-less shooting is the VISION-like host's only scheme
  job.progress.phase("writing outputs");
  r.sol = vision::makeSolution(job.scene, hier, vision::Display::Flat);
  return r;
}
