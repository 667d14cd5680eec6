// Unshot radiant intensity of a sender toward a direction (W/sr), for the far-field estimate of
// interactions with a cluster end. A flat element is one cosine lobe; a curved one a sum of lobes at
// 3 x 3 quadrature points (a whole sphere has no single normal), or its children's sum while its
// normals still spread over more than 30 degrees; a small cluster sums its children exactly, a large
// one (more than State::kTabled surfaces) reads a table filled bottom-up after each pull.
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>

#include "state.h"

namespace vision::detail {
namespace {

constexpr double kNode[3] = {0.1127016653792583, 0.5, 0.8872983346207417};
constexpr double kW[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};

Rgb lobes(const Surface& sf, const Rect& r, const Rgb& U, const Vec3& dir) {
  double sum = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double u = r.u0 + kNode[i] * r.du(), v = r.v0 + kNode[j] * r.dv();
      sum += kW[i] * kW[j] * sf.jacobian(u, v) * std::max(0.0, glm::dot(sf.normal(u, v), dir));
    }
  return U * (sum * r.du() * r.dv() / hr::kPi);
}

Rgb elementIntensity(const State& s, const Element& e, const Rect& rect, const Geometry& g, const Rgb& U, bool part,
                     const Vec3& dir) {
  const Surface& sf = s.h.surfaces()[e.surface];
  if (sf.planar()) return (g.area / hr::kPi) * std::max(0.0, glm::dot(g.coneAxis, dir)) * U;
  if (!part && e.sendKids > 0 && g.coneAngle > hr::kPi / 6.0) {
    Rgb sum(0.0);
    for (int k = 0; k < e.sendKids; ++k) {
      const Element& c = e.kids[k];
      sum += elementIntensity(s, c, c.rect, c.g, c.g.area > 0.0 ? c.P / c.g.area : Rgb(0.0), false, dir);
    }
    return sum;
  }
  return lobes(sf, rect, U, dir);
}

Rgb clusterIntensity(const State& s, std::uint32_t ci, const Vec3& dir) {
  const Cluster& c = s.h.clusters()[ci];
  if (c.table != hr::kNone) return hr::OctaMap::lookup(s.table(c), dir);
  Rgb sum(0.0);
  for (std::uint32_t k : c.clusters) sum += clusterIntensity(s, k, dir);
  for (std::uint32_t k : c.surfaces) {
    const Element& e = s.h.roots()[k];
    if (e.P != Rgb(0.0)) sum += elementIntensity(s, e, e.rect, e.g, e.P / e.g.area, false, dir);
  }
  return sum;
}

void fill(State& s, std::uint32_t ci) {
  const Cluster& c = s.h.clusters()[ci];
  if (c.clusters.size() == 2)
    tbb::parallel_invoke([&] { fill(s, c.clusters[0]); }, [&] { fill(s, c.clusters[1]); });
  if (c.table == hr::kNone) return;
  constexpr int K = hr::OctaMap::kBins;
  float* t = &s.tables[std::size_t(c.table) * K * 3];
  std::fill(t, t + 3 * K, 0.0f);
  if (c.P == Rgb(0.0)) return;
  for (int i = 0; i < K; ++i) {
    const Vec3 d = hr::OctaMap::binDirection(i);
    Rgb sum(0.0);
    for (std::uint32_t k : c.clusters) {
      const Cluster& kc = s.h.clusters()[k];
      if (kc.table != hr::kNone) {
        const float* tk = s.table(kc);
        sum += Rgb(tk[i], tk[K + i], tk[2 * K + i]);
      } else {
        sum += clusterIntensity(s, k, d);
      }
    }
    for (std::uint32_t k : c.surfaces) {
      const Element& e = s.h.roots()[k];
      if (e.P != Rgb(0.0)) sum += elementIntensity(s, e, e.rect, e.g, e.P / e.g.area, false, d);
    }
    t[i] = float(sum.x), t[K + i] = float(sum.y), t[2 * K + i] = float(sum.z);
  }
}

}  // namespace

Rgb unshotIntensity(const State& s, const Sender& snd, const Vec3& dir) {
  if (snd.cluster != hr::kNone) return clusterIntensity(s, snd.cluster, dir);
  return elementIntensity(s, *snd.e, snd.rect, snd.g, snd.U, snd.part, dir);
}

void buildTables(State& s) {
  auto& cl = s.h.clusters();
  if (s.tables.empty()) {
    std::uint32_t n = 0;
    for (Cluster& c : cl) c.table = c.surfaceCount > State::kTabled ? n++ : hr::kNone;
    s.tables.assign(std::size_t(n) * hr::OctaMap::kBins * 3, 0.0f);
  }
  if (!cl.empty()) fill(s, 0);
}

}  // namespace vision::detail
