// The reference tracer's half of the scaling figure (issue 9): the default Cornell box at 256 spp
// (320 x 320 unless told) with 1, 2, 4, ... threads up to the machine's cores, in one run. Prints wall
// time, process CPU time, speedup against one thread, parallel efficiency and CPU / wall, and checks
// that every thread count gives the same image bit for bit.
// Usage: bench_reference_scaling [SPP] [SIZE] [REPEATS]
#include <hr/geometry.h>
#include <hr/scene.h>
#include <ref/path_tracer.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>

int main(int argc, char** argv) {
  const int spp = argc > 1 ? std::atoi(argv[1]) : 256;
  const int size = argc > 2 ? std::atoi(argv[2]) : 320;
  const int repeats = argc > 3 ? std::atoi(argv[3]) : 1;
  hr::Scene scene = hr::defaultScene();
  hr::Camera cam = scene.cameras[0];
  cam.width = cam.height = size;
  hr::TessellationReport rep;
  ref::PathTracer pt(scene, hr::buildPatches(scene, rep));
  ref::Options o;
  o.spp = spp;
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<int> counts;
  // 4 even on fewer cores: oversubscribed, but the image must still be the same bit for bit.
  for (int t = 1; t <= std::max(cores, 4); t *= 2) counts.push_back(t);
  std::printf("reference tracer, Cornell box %d x %d, %d spp, %d core(s); best of %d run(s) per count\n", size, size,
              spp, cores, repeats);
  std::printf("| threads | wall s | CPU s | speedup | efficiency | CPU / wall | same image |\n|---|---|---|---|---|---|---|\n");
  std::vector<float> first;
  double wall1 = 0.0;
  for (int t : counts) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t));
    ref::CameraResult best;
    for (int r = 0; r < repeats; ++r) {
      ref::CameraResult res = pt.render(cam, o);
      if (r == 0 || res.seconds < best.seconds) best = std::move(res);
    }
    if (t == 1) first = best.image.rgb, wall1 = best.seconds;
    bool same = first.size() == best.image.rgb.size() &&
                std::memcmp(first.data(), best.image.rgb.data(), first.size() * sizeof(float)) == 0;
    double speedup = wall1 / best.seconds;
    std::printf("| %d | %.2f | %.2f | %.2f | %.2f | %.2f | %s |\n", t, best.seconds, best.cpuSeconds, speedup,
                speedup / std::min(t, cores), best.cpuSeconds / best.seconds, same ? "yes" : "NO");
    if (!same) return 1;
  }
  return 0;
}
