// What accuracy costs in time, on the default scene (96 x 96 pixels), in one run: a long path-traced
// reference (2048 samples per pixel), then path tracing at 8-256 spp and the radiosity solver at three
// thresholds, each compared with the long reference (relative RMSE of luminance, mean ratio). The
// reference's own noise floor is printed with it.
#include <hr/output.h>
#include <hr/solver.h>
#include <ref/compare.h>
#include <ref/path_tracer.h>

#include <chrono>
#include <cmath>
#include <cstdio>

namespace {

/// The light panel's pixels say nothing about the solution (constant emission) but dominate the
/// error through their edges: blank them in both images.
hr::Image withoutObject(hr::Image img, std::uint32_t object) {
  for (std::size_t i = 0; i < img.objectId.size(); ++i)
    if (img.objectId[i] == object) img.rgb[3 * i] = img.rgb[3 * i + 1] = img.rgb[3 * i + 2] = 0.0f;
  return img;
}

double since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

int main(int argc, char** argv) {
  const int refSpp = argc > 1 ? std::atoi(argv[1]) : 2048;
  hr::Scene scene = hr::defaultScene();
  hr::Camera cam = scene.cameras[0];
  cam.width = cam.height = 96;
  hr::TessellationReport rep;
  ref::PathTracer pt(scene, hr::buildPatches(scene, rep));
  ref::Options o;
  o.spp = refSpp;
  o.seed = 1000;
  auto t0 = std::chrono::steady_clock::now();
  ref::CameraResult reference = pt.render(cam, o);
  double floor2 = 0.0;
  for (std::size_t i = 1; i < reference.variance.size(); i += 3) floor2 += reference.variance[i];
  double floorRmse = std::sqrt(floor2 / double(cam.width * cam.height)) / reference.meanLuminance;
  std::printf("reference: %d spp in %.1f s; its own noise: relative RMSE ~%.4f (green channel), mean +-%.3f %%\n\n", refSpp,
              since(t0), floorRmse, 100.0 * reference.relStdError);
  const std::uint32_t light = 5;  // the Cornell box's light panel, in file order
  hr::Image refImg = withoutObject(reference.image, light);
  std::printf("(errors over all pixels but the light panel's)\n");
  std::printf("| method | setting | seconds | rel RMSE | mean ratio |\n|---|---|---|---|---|\n");
  for (int spp : {8, 16, 64, 256}) {  // whole rounds of the 8 replicates
    o.spp = spp;
    o.seed = 7;
    auto t = std::chrono::steady_clock::now();
    ref::CameraResult r = pt.render(cam, o);
    double s = since(t);
    ref::Metrics m = ref::compare(withoutObject(r.image, light), refImg);
    std::printf("| path tracing | %d spp | %.3f | %.4f | %.4f |\n", spp, s, m.relRmse, m.meanRatio);
  }
  for (double eps : {1e-3, 2e-4, 5e-5}) {
    auto t = std::chrono::steady_clock::now();
    hr::TessellationReport rr;
    hr::Hierarchy h(hr::buildPatches(scene, rr));
    hr::Visibility vis(h.patches());
    hr::SolverOptions so = hr::SolverOptions::from(scene.settings);
    so.eps = eps;
    hr::Solver solver(scene, h, vis, so);
    solver.solve();
    hr::Solution sol = hr::makeSolution(scene, h, solver.radiosity());
    hr::Image img = hr::render(sol, cam);
    double s = since(t);
    ref::Metrics m = ref::compare(withoutObject(img, light), refImg);
    std::printf("| radiosity | eps %.0e | %.3f | %.4f | %.4f |\n", eps, s, m.relRmse, m.meanRatio);
  }
  return 0;
}
