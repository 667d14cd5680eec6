// A fixed octahedral map of directions: the host's cheap record of a cluster's exitant intensity
// (clusters of diffuse elements are not isotropic, so a single number will not do). Bilinear lookup.
#pragma once
#include <hr/types.h>

#include <vector>

namespace hr {

class OctaMap {
 public:
  static constexpr int kRes = 16;
  static constexpr int kBins = kRes * kRes;

  static Vec2 encode(const Vec3& d) {
    double s = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
    Vec2 p(d.x / s, d.y / s);
    if (d.z < 0.0) p = Vec2((1.0 - std::abs(p.y)) * (p.x >= 0 ? 1 : -1), (1.0 - std::abs(p.x)) * (p.y >= 0 ? 1 : -1));
    return 0.5 * (p + Vec2(1.0));
  }
  static Vec3 decode(Vec2 uv) {
    Vec2 p = 2.0 * uv - Vec2(1.0);
    Vec3 d(p.x, p.y, 1.0 - std::abs(p.x) - std::abs(p.y));
    if (d.z < 0.0) {
      double x = d.x, y = d.y;
      d.x = (1.0 - std::abs(y)) * (x >= 0 ? 1 : -1);
      d.y = (1.0 - std::abs(x)) * (y >= 0 ? 1 : -1);
    }
    return glm::normalize(d);
  }
  static Vec3 binDirection(int i) { return decode(Vec2((i % kRes + 0.5) / kRes, (i / kRes + 0.5) / kRes)); }

  /// Bilinear lookup of a table at direction d. Tables are planar: kBins reds, then greens, then
  /// blues, so that adding a cosine lobe to every bin vectorises.
  static Rgb lookup(const float* table, const Vec3& d) {
    Vec2 uv = encode(d) * double(kRes) - Vec2(0.5);
    int x0 = static_cast<int>(std::floor(uv.x)), y0 = static_cast<int>(std::floor(uv.y));
    double fx = uv.x - x0, fy = uv.y - y0;
    Rgb r(0.0);
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        int x = glm::clamp(x0 + dx, 0, kRes - 1), y = glm::clamp(y0 + dy, 0, kRes - 1);
        double w = (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy);
        const int b = y * kRes + x;
        r += w * Rgb(table[b], table[kBins + b], table[2 * kBins + b]);
      }
    return r;
  }
};

}  // namespace hr
