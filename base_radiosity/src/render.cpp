// Still images from a stored solution: one primary ray per pixel through Embree, shaded by the
// display hook (default: smooth diffuse reconstruction). The same per-leaf radiance drives the
// interactive viewer, so images and walkthroughs agree.
#include <hr/output.h>
#include <hr/visibility.h>
#include <tbb/parallel_for.h>

#include <cmath>

namespace hr {

Image render(const Solution& s, const Camera& cam, const DisplayFn& display) {
  Visibility vis(s.patches);
  Image img;
  img.width = cam.width;
  img.height = cam.height;
  img.rgb.assign(std::size_t(cam.width) * cam.height * 3, 0.0f);
  img.objectId.assign(std::size_t(cam.width) * cam.height, kNone);
  Vec3 f = glm::normalize(cam.lookAt - cam.eye);
  Vec3 r = glm::normalize(glm::cross(f, cam.up));
  Vec3 u = glm::cross(r, f);
  double th = std::tan(0.5 * cam.fovYDeg * kPi / 180.0);
  double aspect = double(cam.width) / cam.height;
  tbb::parallel_for(0, cam.height, [&](int y) {
    for (int x = 0; x < cam.width; ++x) {
      double px = (2.0 * (x + 0.5) / cam.width - 1.0) * th * aspect;
      double py = (1.0 - 2.0 * (y + 0.5) / cam.height) * th;
      Vec3 d = glm::normalize(f + px * r + py * u);
      SurfaceHit hit = vis.intersect(cam.eye, d);
      if (!hit.hit) continue;
      Vec3 p = cam.eye + hit.t * d;
      const Patch& pt = s.patches[hit.patch];
      std::size_t i = std::size_t(y) * cam.width + x;
      img.objectId[i] = pt.object;
      // Surfaces emit and reflect from their front only; their back shows black.
      if (glm::dot(pt.normal, d) >= 0.0) continue;
      std::uint32_t leaf = locateLeaf(s, hit.patch, p);
      Rgb L = display ? display(leaf, p, -d) : interpolate(s, leaf, p) / kPi;
      for (int c = 0; c < 3; ++c) img.rgb[3 * i + c] = std::isfinite(L[c]) ? static_cast<float>(L[c]) : 0.0f;
    }
  });
  return img;
}

}  // namespace hr
