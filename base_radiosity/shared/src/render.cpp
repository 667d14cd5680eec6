// Still images from a stored solution: a grid of primary rays per pixel through Embree, shaded by the
// display hook (default: smooth diffuse reconstruction). The same per-leaf radiance drives the
// interactive viewer, so images and walkthroughs agree.
#include <hr/camera.h>
#include <hr/extension_display.h>
#include <hr/output.h>
#include <hr/visibility.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hr {

namespace {

/// A pixel whose grid samples' luminance spans more than this fraction of their largest is sampled
/// again on a grid three times finer per axis (the coarse points among them): an edge, a hard
/// shadow's or a highlight's. floor_gloss's shiny sphere showed its lamp in pixels 1 % off their
/// average on 3 x 3 points, about the hosts' own error there (the reference averages each pixel);
/// refined, the VISION-like image went 0.072 -> 0.062 from its reference, the glossy Cornell box's
/// 0.052 -> 0.049, for twice the render time on floor_gloss (0.1 refined more pixels for no gain).
constexpr double kRefineContrast = 0.5;

}  // namespace

Image render(const Solution& s, const Camera& cam, const DisplayFn& display, int samplesPerAxis) {
  Visibility vis(s.patches);
  Image img;
  img.width = cam.width;
  img.height = cam.height;
  img.rgb.assign(std::size_t(cam.width) * cam.height * 3, 0.0f);
  img.objectId.assign(std::size_t(cam.width) * cam.height, kNone);
  CameraRays rays(cam);
  // The radiance along the ray through pixel coordinates (px, py); the object hit, kNone for none.
  auto shade = [&](double px, double py, std::uint32_t* object) {
    const Vec3 d = rays.dir(px, py);
    SurfaceHit hit = vis.intersect(cam.eye, d);
    if (!hit.hit) return Rgb(0.0);
    const Patch& pt = s.patches[hit.patch];
    if (object) *object = pt.object;
    // Surfaces emit and reflect from their front only; their back shows black.
    if (glm::dot(pt.normal, d) >= 0.0) return Rgb(0.0);
    Vec3 p = cam.eye + hit.t * d;
    std::uint32_t leaf = locateLeaf(s, hit.patch, p);
    Rgb L = display ? display(leaf, p, -d) : interpolate(s, leaf, p) / kPi;
    return allFinite(L) ? L : Rgb(0.0);
  };
  const int k = std::max(samplesPerAxis, 1), fine = 3 * k;
  tbb::parallel_for(0, cam.height, [&](int y) {
    for (int x = 0; x < cam.width; ++x) {
      std::size_t i = std::size_t(y) * cam.width + x;
      Rgb sum(0.0);
      double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
      // A regular k x k grid over the pixel: the image holds pixel averages, as the path-traced
      // reference does, so that the two compare pixel for pixel (edges of a bright light included).
      for (int sy = 0; sy < k; ++sy)
        for (int sx = 0; sx < k; ++sx) {
          const bool centre = 2 * sx + 1 == k && 2 * sy + 1 == k;
          const Rgb L = shade(x + (sx + 0.5) / k, y + (sy + 0.5) / k, centre ? &img.objectId[i] : nullptr);
          sum += L;
          lo = std::min(lo, luminance(L)), hi = std::max(hi, luminance(L));
        }
      if (hi - lo > kRefineContrast * hi) {
        // The fine grid's points (3 a + 1, 3 b + 1) are the coarse ones: only the others are cast.
        for (int sy = 0; sy < fine; ++sy)
          for (int sx = 0; sx < fine; ++sx)
            if (sx % 3 != 1 || sy % 3 != 1) sum += shade(x + (sx + 0.5) / fine, y + (sy + 0.5) / fine, nullptr);
        sum /= double(fine * fine);
      } else {
        sum /= double(k * k);
      }
      for (int c = 0; c < 3; ++c) img.rgb[3 * i + c] = static_cast<float>(sum[c]);
      if (k % 2 == 0) {  // no grid sample at the centre: cast one for the object id
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
