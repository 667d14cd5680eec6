// An image from the path tracer: the camera's pixels in fixed 16 x 16 tiles, run in parallel; in a
// tile, 16 paths advance together (one rtcIntersect16 for their rays, one rtcOccluded16 for their
// shadow rays) and a finished path's lane takes the tile's next sample at once, so packets stay full.
// Each tile sums its samples in an order fixed by the tile alone, hence images independent of the
// thread count.
#include <hr/camera.h>
#include <ref/path_tracer.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <ctime>

namespace ref {

namespace {

constexpr int kTile = 16;
constexpr int kLanes = 16;

double processCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// Per pixel and replicate: the sum of the samples (RGB and luminance) and their count, from which
/// the mean and, through the spread of the replicates' means, its variance.
struct Accumulator {
  static constexpr int kSums = 4;  // R, G, B, luminance
  std::vector<double> sum;
  std::vector<std::uint32_t> count, bad;
  explicit Accumulator(std::size_t pixels)
      : sum(pixels * kReplicates * kSums, 0.0), count(pixels * kReplicates, 0), bad(pixels, 0) {}
  void add(std::size_t i, int sample, const Rgb& L) {
    if (!hr::allFinite(L)) {
      ++bad[i];
      return;
    }
    std::size_t cell = i * kReplicates + std::size_t(sample % kReplicates);
    double* s = &sum[cell * kSums];
    s[0] += L.x, s[1] += L.y, s[2] += L.z, s[3] += hr::luminance(L);
    ++count[cell];
  }
};

struct Tile {
  int x0, y0, x1, y1;
};

}  // namespace

CameraResult PathTracer::render(const hr::Camera& cam, const Options& o, hr::Progress* progress) const {
  CameraResult r;
  const std::size_t P = std::size_t(cam.width) * cam.height;
  const hr::CameraRays rays(cam);
  std::vector<Tile> tiles;
  for (int y = 0; y < cam.height; y += kTile)
    for (int x = 0; x < cam.width; x += kTile)
      tiles.push_back({x, y, std::min(x + kTile, cam.width), std::min(y + kTile, cam.height)});
  r.image.width = cam.width;
  r.image.height = cam.height;
  r.image.objectId.assign(P, hr::kNone);
  tbb::parallel_for(std::size_t(0), tiles.size(), [&](std::size_t t) {
    const Tile& tile = tiles[t];
    std::array<Vec3, kLanes> org, dir;
    std::array<hr::SurfaceHit, kLanes> hits;
    std::array<std::size_t, kLanes> at;
    int n = 0;
    auto flush = [&] {
      vis_->intersect(org.data(), dir.data(), n, hits.data());
      for (int k = 0; k < n; ++k)
        if (hits[k].hit) r.image.objectId[at[k]] = patches_[hits[k].patch].object;
      n = 0;
    };
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        org[n] = rays.origin(), dir[n] = rays.dir(x + 0.5, y + 0.5), at[n] = std::size_t(y) * cam.width + x;
        if (++n == kLanes) flush();
      }
    if (n) flush();
  });

  Accumulator acc(P);
  auto traceTile = [&](const Tile& tile, int s0, int s1) {
    std::array<PathState, kLanes> lane;
    std::array<std::size_t, kLanes> pixel{};
    std::array<int, kLanes> sample{};
    std::array<int, kLanes> idx{};
    std::array<Vec3, kLanes> org, dir, from, to;
    std::array<hr::SurfaceHit, kLanes> hits;
    // The next sample to start: sample index by sample index, each over the tile's pixels.
    int s = s0, x = tile.x0, y = tile.y0;
    while (true) {
      for (int k = 0; k < kLanes; ++k) {
        if (lane[k].alive || s >= s1) continue;
        pixel[k] = std::size_t(y) * cam.width + x;
        sample[k] = s;
        SampleStream ss(o.seed, pixel[k], std::uint64_t(s));
        Uv u = ss.get2D();
        lane[k].start(rays.origin(), rays.dir(x + u.u, y + u.v), ss);
        if (++x == tile.x1 && (x = tile.x0, ++y == tile.y1)) y = tile.y0, ++s;
      }
      int n = 0;
      for (int k = 0; k < kLanes; ++k)
        if (lane[k].alive) idx[n] = k, org[n] = lane[k].org, dir[n] = lane[k].dir, ++n;
      if (n == 0) break;
      vis_->intersect(org.data(), dir.data(), n, hits.data());
      int m = 0;
      for (int q = 0; q < n; ++q) {
        PathState& p = lane[idx[q]];
        shade(p, hits[q], o.maxDepth);
        if (p.shadow) from[m] = p.shadowFrom, to[m] = p.shadowTo, idx[m] = idx[q], ++m;
        else if (!p.alive) acc.add(pixel[idx[q]], sample[idx[q]], p.radiance);
      }
      std::array<bool, kLanes> bl{};
      vis_->occluded(from.data(), to.data(), m, bl.data());
      for (int q = 0; q < m; ++q) {
        PathState& p = lane[idx[q]];
        if (!bl[q]) p.radiance += p.shadowRadiance;
        if (!p.alive) acc.add(pixel[idx[q]], sample[idx[q]], p.radiance);
      }
    }
  };

  auto t0 = std::chrono::steady_clock::now();
  double c0 = processCpuSeconds();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  // Whole rounds of replicates: the variance estimate needs every replicate equally filled.
  const int spp = (std::max(1, o.spp) + kReplicates - 1) / kReplicates * kReplicates;
  const int passSpp = (std::max(1, o.passSpp) + kReplicates - 1) / kReplicates * kReplicates;
  int done = 0;
  while (true) {
    int pass = o.timeS > 0.0 ? passSpp : std::min(passSpp, spp - done);
    if (pass <= 0) break;
    tbb::parallel_for(std::size_t(0), tiles.size(), [&](std::size_t t) { traceTile(tiles[t], done, done + pass); });
    done += pass;
    if (progress) progress->update(o.timeS > 0.0 ? std::min(1.0, elapsed() / o.timeS) : double(done) / spp);
    if (o.timeS > 0.0 && elapsed() >= o.timeS) break;
  }
  r.seconds = elapsed();
  r.cpuSeconds = processCpuSeconds() - c0;
  r.spp = done;
  r.paths = std::uint64_t(done) * P;
  r.image.rgb.assign(3 * P, 0.0f);
  r.variance.assign(3 * P, 0.0f);
  double mean = 0.0, varMean = 0.0;
  for (std::size_t i = 0; i < P; ++i) {
    r.nonFinite += acc.bad[i];
    double m[4] = {0, 0, 0, 0}, rep[kReplicates][4];
    std::uint32_t n = 0;
    bool complete = true;
    for (int k = 0; k < kReplicates; ++k) {
      std::size_t cell = i * kReplicates + std::size_t(k);
      n += acc.count[cell];
      complete = complete && acc.count[cell] > 0;
      for (int c = 0; c < 4; ++c) {
        m[c] += acc.sum[cell * Accumulator::kSums + c];
        rep[k][c] = acc.count[cell] ? acc.sum[cell * Accumulator::kSums + c] / acc.count[cell] : 0.0;
      }
    }
    if (n == 0) continue;
    for (double& c : m) c /= double(n);
    // Variance of the mean of kReplicates independent replicate means.
    double v[4] = {0, 0, 0, 0};
    for (int k = 0; complete && k < kReplicates; ++k)
      for (int c = 0; c < 4; ++c) v[c] += (rep[k][c] - m[c]) * (rep[k][c] - m[c]) / (kReplicates * (kReplicates - 1.0));
    for (int c = 0; c < 3; ++c) {
      r.image.rgb[3 * i + c] = static_cast<float>(m[c]);
      r.variance[3 * i + c] = static_cast<float>(v[c]);
    }
    mean += m[3];
    varMean += v[3];
  }
  r.meanLuminance = mean / double(P);
  r.relStdError = r.meanLuminance > 0.0 ? std::sqrt(varMean) / double(P) / r.meanLuminance : 0.0;
  return r;
}

}  // namespace ref
