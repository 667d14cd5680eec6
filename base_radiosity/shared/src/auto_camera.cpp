// Automatic camera placement (auto_camera.h): an outside framing for open scenes, an eye inside for
// enclosed ones, chosen by how much of the scene each view shows from the front.
#include <hr/auto_camera.h>
#include <hr/camera.h>

#include <array>
#include <cmath>

namespace hr {

void UpEvidence::add(const Vec3& n, double area, bool emitter) {
  if (emitter) {
    emitterNormals += area * n;
    emitterArea += area;
  }
  for (int k = 0; k < 3; ++k)
    if (std::abs(n[k]) > 0.9) alignedArea[k] += area;
}

Vec3 upAxis(const UpEvidence& e) {
  const Vec3& n = e.emitterNormals;
  double len = glm::length(n);
  int k = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(n[a]) > std::abs(n[k])) k = a;
  Vec3 up(0.0);
  if (len > 0.3 * e.emitterArea && std::abs(n[k]) >= 0.8 * len) {
    up[k] = n[k] > 0.0 ? -1.0 : 1.0;
    return up;
  }
  k = 1;  // y unless another axis holds strictly more aligned area
  for (int a : {2, 0})
    if (e.alignedArea[a] > e.alignedArea[k]) k = a;
  up[k] = 1.0;
  return up;
}

ViewScore scoreView(const Camera& c, const Aabb& box, const ViewProbe& probe) {
  constexpr int kW = 32, kH = 24;
  Camera grid = c;
  grid.width = kW;
  grid.height = kH;
  CameraRays rays(grid);
  double near = 0.02 * box.diagonal();
  int seen = 0, escaped = 0;
  for (int j = 0; j < kH; ++j)
    for (int i = 0; i < kW; ++i) {
      ProbeHit h = probe(rays.origin(), rays.dir(i + 0.5, j + 0.5));
      if (h.hit && h.front && h.t > near) ++seen;
      if (!h.hit) ++escaped;
    }
  return {double(seen) / (kW * kH), double(escaped) / (kW * kH)};
}

Camera autoCamera(const Aabb& box, const Vec3& up, const ViewProbe& probe) {
  // The frame (side, up, back): +y up gives (x, y, z), the previous outside camera's frame.
  int k = std::abs(up.x) > 0.5 ? 0 : std::abs(up.y) > 0.5 ? 1 : 2;
  Vec3 back(0.0), side(0.0);
  back[(k + 1) % 3] = 1.0;
  side[(k + 2) % 3] = 1.0;
  Camera outside;
  outside.name = "auto";
  outside.up = up;
  outside.lookAt = box.center();
  double r = 0.5 * box.diagonal();
  outside.eye = outside.lookAt + r * (0.5 * side + 1.4 * up + 2.3 * back);  // 30 degrees above
  outside.fovYDeg = 45;
  outside.width = 320;
  outside.height = 240;
  if (box.empty() || !(r > 0.0)) return outside;

  Camera best = outside;
  double bestScore = scoreView(outside, box, probe).front;
  Vec3 half = 0.5 * box.extent(), c = box.center();
  double height = glm::dot(up, c) + 0.2 * std::abs(glm::dot(up, half));  // 60 % of the way up
  std::array<Vec3, 4> walls = {back, -back, side, -side};
  for (const Vec3& w : walls) {
    Camera in = outside;
    Vec3 across = c - 0.85 * std::abs(glm::dot(w, half)) * w;  // near the wall opposite w...
    in.eye = across + (height - glm::dot(up, across)) * up;
    in.lookAt = c + (height - glm::dot(up, c)) * up - 0.25 * std::abs(glm::dot(up, half)) * up;  // ...looking along w
    in.fovYDeg = 60;
    ViewScore score = scoreView(in, box, probe);
    if (score.escaped <= 0.02 && score.front > bestScore + 0.05) {
      best = in;
      bestScore = score.front;
    }
  }
  return best;
}

Camera autoCamera(const Scene& scene, const std::vector<Patch>& patches, const Visibility& vis) {
  Aabb box;
  UpEvidence up;
  for (const Patch& p : patches) {
    for (int k = 0; k < p.poly.n; ++k) box.grow(p.poly.v[k]);
    up.add(p.normal, p.area, scene.materials[p.material].emitter());
  }
  return autoCamera(box, upAxis(up), [&](const Vec3& o, const Vec3& d) {
    SurfaceHit h = vis.intersect(o, d);
    return ProbeHit{h.hit, h.t, h.hit && glm::dot(patches[h.patch].normal, d) < 0.0};
  });
}

}  // namespace hr
