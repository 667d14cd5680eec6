// Visibility throughput of the solver's bundled segment queries (rtcOccluded16, as the rays of one
// link are traced) against a raw rtcOccluded1 loop over the same segments and Embree scene, in one
// run; prints rays per second of both and their ratio.
#include <embree3/rtcore.h>
#include <hr/rng.h>
#include <hr/visibility.h>

#include <chrono>
#include <cstdio>
#include <limits>

int main() {
  hr::Scene sc = hr::defaultScene();
  hr::TessellationReport rep;
  auto patches = hr::buildPatches(sc, rep);
  hr::Visibility vis(patches);
  // Segments between points on random patch pairs, 16 per "link", as the solver draws them.
  const int N = 1 << 20;
  std::vector<hr::Vec3> from(N), to(N);
  hr::Rng rng(3, 3);
  for (int i = 0; i < N; i += 16) {
    auto& a = patches[rng.next() % patches.size()].poly;
    auto& b = patches[rng.next() % patches.size()].poly;
    for (int k = 0; k < 16; ++k) {
      from[i + k] = a.sample(rng.uniform(), rng.uniform());
      to[i + k] = b.sample(rng.uniform(), rng.uniform());
    }
  }
  auto* scene = static_cast<RTCScene>(vis.rawScene());
  const double eps = vis.epsilon();
  std::vector<char> b1(N);
  bool b16[16];
  double best16 = 1e30, best1 = 1e30;
  long blocked16 = 0, blocked1 = 0;
  for (int rep2 = 0; rep2 < 3; ++rep2) {
    auto t0 = std::chrono::steady_clock::now();
    blocked16 = 0;
    for (int i = 0; i < N; i += 16) {
      vis.occluded(&from[i], &to[i], 16, b16);
      for (int k = 0; k < 16; ++k) blocked16 += b16[k];
    }
    auto t1 = std::chrono::steady_clock::now();
    blocked1 = 0;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (int i = 0; i < N; ++i) {
      hr::Vec3 d = to[i] - from[i];
      double len = glm::length(d);
      RTCRay r;
      r.org_x = float(from[i].x), r.org_y = float(from[i].y), r.org_z = float(from[i].z);
      r.dir_x = float(d.x), r.dir_y = float(d.y), r.dir_z = float(d.z);
      r.tnear = float(eps / len), r.tfar = float(1.0 - eps / len);
      r.time = 0, r.mask = ~0u, r.id = 0, r.flags = 0;
      rtcOccluded1(scene, &ctx, &r);
      blocked1 += r.tfar < 0.0f;
    }
    auto t2 = std::chrono::steady_clock::now();
    best16 = std::min(best16, std::chrono::duration<double>(t1 - t0).count());
    best1 = std::min(best1, std::chrono::duration<double>(t2 - t1).count());
  }
  std::printf("rays %d (blocked: solver %ld, raw %ld)\n", N, blocked16, blocked1);
  std::printf("solver bundled occluded16: %.3g rays/s\n", N / best16);
  std::printf("raw rtcOccluded1 loop:     %.3g rays/s\n", N / best1);
  std::printf("ratio solver/raw: %.2f\n", best1 / best16);
  return 0;
}
