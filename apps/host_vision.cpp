// `--host vision`: the VISION-like host in vision_host, with the extension (if any) through its
// hooks and adapters/vision for the display cells of its solution.
#include <hr/auto_camera.h>
#include <vision/solver.h>

#include "vision/display_cells.h"

#include <cstdio>
#include <memory>

#include "host_front.h"

namespace {

/// What the extension's views point into, alive as long as the result is.
struct VisionRun {
  std::unique_ptr<vision::Hierarchy> hier;
  std::unique_ptr<vision::CurvedVisibility> vis;
  std::unique_ptr<vision::Solver> solver;
};

// The auto camera probes the exact curved surfaces; the up axis's evidence is sampled on a 4 x 4
// parameter grid of every surface (area-weighted by the Jacobian).
hr::Camera autoCamera(const hr::Scene& scene, const vision::Hierarchy& hier, const vision::CurvedVisibility& vis) {
  hr::UpEvidence up;
  for (const vision::Surface& s : hier.surfaces()) {
    bool emitter = scene.materials[s.material].emitter();
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        double u = (i + 0.5) / 4, v = (j + 0.5) / 4;
        up.add(s.normal(u, v), s.jacobian(u, v) / 16.0, emitter);
      }
  }
  return hr::autoCamera(hier.bounds(), hr::upAxis(up), [&](const hr::Vec3& o, const hr::Vec3& d) {
    vision::CurvedHit h = vis.intersect(o, d);
    return hr::ProbeHit{h.hit, h.t, h.front};
  });
}

}  // namespace

HostResult solveVision(HostJob& job) {
  job.progress.phase("building surfaces");
  vision::SurfaceReport rep;
  std::vector<vision::Surface> surfaces = vision::buildSurfaces(job.scene, rep);
  if (rep.dropped) std::fprintf(stderr, "warning: dropped %zu zero-area face(s)\n", rep.dropped);
  if (rep.nonPlanarQuads) std::fprintf(stderr, "warning: split %zu non-planar quad(s) into triangles\n", rep.nonPlanarQuads);
  if (rep.split) std::fprintf(stderr, "note: %zu extra surface(s) from polygons not star-shaped about their centroid\n", rep.split);
  dropUnneededExtension(job);
  if (job.ext) job.ext = adapters::vision::adapt(std::move(job.ext));
  auto run = std::make_shared<VisionRun>();
  run->hier = std::make_unique<vision::Hierarchy>(std::move(surfaces));
  job.progress.phase("building visibility");
  run->vis = std::make_unique<vision::CurvedVisibility>(run->hier->surfaces());
  if (job.scene.cameras.empty()) job.scene.cameras.push_back(autoCamera(job.scene, *run->hier, *run->vis));
  job.ready();
  run->solver = std::make_unique<vision::Solver>(job.scene, *run->hier, *run->vis, job.opt, job.ext.get(), &job.progress);
  HostResult r;
  r.st = run->solver->solve();
  r.st.iteration = hr::Iteration::Shoot;  // link-less shooting is the VISION-like host's only scheme
  job.progress.phase("writing outputs");
  std::vector<std::uint32_t> cellLeaf;
  r.sol = vision::makeSolution(job.scene, *run->hier, vision::Display::Smooth, &cellLeaf);
  if (job.ext) adapters::vision::showCells(*job.ext, run->solver->view(), r.sol, cellLeaf);
  r.keep = run;
  return r;
}
