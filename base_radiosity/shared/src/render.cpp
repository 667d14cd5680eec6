// Still images from a stored solution: a grid of primary rays per pixel through Embree, shaded by the
// display hook (default: smooth diffuse reconstruction). The same per-leaf radiance drives the
// interactive viewer, so images and walkthroughs agree.
#include <hr/camera.h>
#include <hr/extension_display.h>
#include <hr/output.h>
#include <hr/visibility.h>
#include <tbb/parallel_for.h>

#include <cmath>

namespace hr {

Image render(const Solution& s, const Camera& cam, const DisplayFn& display, int samplesPerAxis) {
  Visibility vis(s.patches);
  Image img;
  img.width = cam.width;
  img.height = cam.height;
  img.rgb.assign(std::size_t(cam.width) * cam.height * 3, 0.0f);
  img.objectId.assign(std::size_t(cam.width) * cam.height, kNone);
  CameraRays rays(cam);
  tbb::parallel_for(0, cam.height, [&](int y) {
    for (int x = 0; x < cam.width; ++x) {
      std::size_t i = std::size_t(y) * cam.width + x;
      Rgb sum(0.0);
      // A regular k x k grid over the pixel: the image holds pixel averages, as the path-traced
      // reference does, so that the two compare pixel for pixel (edges of a bright light included).
      for (int sy = 0; sy < samplesPerAxis; ++sy)
        for (int sx = 0; sx < samplesPerAxis; ++sx) {
          Vec3 d = rays.dir(x + (sx + 0.5) / samplesPerAxis, y + (sy + 0.5) / samplesPerAxis);
          SurfaceHit hit = vis.intersect(cam.eye, d);
          if (!hit.hit) continue;
          const Patch& pt = s.patches[hit.patch];
          if (2 * sx + 1 == samplesPerAxis && 2 * sy + 1 == samplesPerAxis) img.objectId[i] = pt.object;
          // Surfaces emit and reflect from their front only; their back shows black.
          if (glm::dot(pt.normal, d) >= 0.0) continue;
          Vec3 p = cam.eye + hit.t * d;
          std::uint32_t leaf = locateLeaf(s, hit.patch, p);
          Rgb L = display ? display(leaf, p, -d) : interpolate(s, leaf, p) / kPi;
          if (allFinite(L)) sum += L;
        }
      sum /= double(samplesPerAxis * samplesPerAxis);
      for (int c = 0; c < 3; ++c) img.rgb[3 * i + c] = static_cast<float>(sum[c]);
      if (samplesPerAxis % 2 == 0) {  // no grid sample at the centre: cast one for the object id
        SurfaceHit centre = vis.intersect(cam.eye, rays.dir(x + 0.5, y + 0.5));
        if (centre.hit) img.objectId[i] = s.patches[centre.patch].object;
      }
    }
  });
  return img;
}

Image render(const Solution& s, const Camera& cam, const Extension* ext) {
  if (!ext) return render(s, cam);
  // The host's smooth B / pi plus the extension's share, smooth per display vertex toward this eye.
  ExtensionDisplay display(s, *ext);
  display.update(cam.eye);
  return render(s, cam, [&](std::uint32_t leaf, const Vec3& x, const Vec3& toEye) {
    return interpolate(s, leaf, x) / kPi + display.radiance(leaf, x, toEye);
  });
}

}  // namespace hr
