// Smooth display of the Lambertian radiosity without bias (issue 10, item 4).
//
// A leaf corner takes the area-weighted mean radiosity of the leaves that share the point, face
// within 30 degrees of it and belong to the same object and material: light never blends across
// objects, materials or emitters (a lamp flush with a ceiling must not halo onto it). Nor does a
// visible leaf take the radiosity of a hidden one: a leaf with a surface in front of it closer than
// a tenth of its size (the ceiling 1 mm above the Cornell box's lamp, a floor under a box standing
// on it) or under a coplanar cover is dark for a reason that stops at its edge, a discontinuity of
// the radiosity, which averaging smeared as a dark ring onto the visible neighbours: measured on
// the Cornell box, the ceiling drew 1.7 % darker than its own leaves and the floor 0.6 %; the
// image 0.3 %. (A centre value per leaf that keeps each leaf's drawn mean exact was tried: unbiased
// by construction, but it drew element-sized ripples wherever corners and mean disagree.)
// Averaged corners still draw a curved falloff too bright where it is convex and too dark where it
// is concave, by up to a leaf's width squared times the curvature; so the corners are then moved,
// together and within their leaves' range, toward drawing each leaf's own mean (kMeanPasses).
#include <hr/solution.h>
#include <hr/visibility.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstring>
#include <unordered_map>

namespace hr {

std::vector<char> hiddenLeaves(const Solution& s) {
  Visibility vis(s.patches);
  std::vector<char> hidden(s.elements.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, std::uint32_t(s.elements.size()), 256), [&](const auto& r) {
    for (std::uint32_t i = r.begin(); i != r.end(); ++i) {
      const auto& e = s.elements[i];
      if (!e.leaf()) continue;
      const Vec3 c = e.poly.centroid();
      if (vis.coverOf(e.patch, c) != kNone) {
        hidden[i] = 1;
        continue;
      }
      SurfaceHit hit = vis.intersectFrom(c, s.patches[e.patch].normal, e.patch);
      hidden[i] = hit.hit && hit.t < 0.1 * std::sqrt(e.poly.area()) ? 1 : 0;
    }
  });
  return hidden;
}

/// The mean over a leaf of what interpolateCorners draws from corner values cv.
Rgb drawnMean(const Solution& s, std::uint32_t leaf, const std::array<Rgb, 4>& cv) {
  const auto& e = s.elements[leaf];
  if (e.poly.n == 3) return (cv[0] + cv[1] + cv[2]) / 3.0;
  // Quads: four triangles around the centroid, whose value is the corners' mean.
  const Vec3 c = e.poly.centroid();
  const Rgb m = 0.25 * (cv[0] + cv[1] + cv[2] + cv[3]);
  Rgb sum(0.0);
  double area = 0.0;
  for (int k = 0; k < 4; ++k) {
    const double a = 0.5 * glm::length(glm::cross(e.poly.v[k] - c, e.poly.v[(k + 1) % 4] - c));
    sum += a * (cv[k] + cv[(k + 1) % 4] + m) / 3.0;
    area += a;
  }
  return area > 0.0 ? sum / area : m;
}

void reconstruct(Solution& s) {
  const std::string* surfaces = findSection(s, kSurfaces);
  s.surfaces = surfaces ? decodeSurfaces(*surfaces, s.objectCount) : std::vector<CurvedSurface>();
  // A solution saved for flat display (a "display" section saying "flat": one value per element, as
  // the VISION-like host shows its solutions) keeps every corner at its element's radiosity.
  const std::string* d = findSection(s, "display");
  if (d && *d == "flat") {
    s.cornerRadiosity.assign(s.elements.size(), {});
    for (std::size_t i = 0; i < s.elements.size(); ++i) s.cornerRadiosity[i].fill(s.elements[i].radiosity);
    return;
  }
  // A host that smooths in its own terms (the VISION-like host, in parameter space) saves the corners.
  if (d && d->rfind(kDisplayCorners, 0) == 0) {
    s.cornerRadiosity = decodeDisplayCorners(s, *d);
    return;
  }
  Aabb box;
  for (const Patch& p : s.patches)
    for (int k = 0; k < p.poly.n; ++k) box.grow(p.poly.v[k]);
  const double q = std::max(box.diagonal(), 1e-300) * 1e-7;
  auto key = [&](const Vec3& p) {
    auto c = [&](double v) { return static_cast<std::int64_t>(std::llround(v / q)); };
    std::uint64_t k = static_cast<std::uint64_t>(c(p.x)) * 73856093ull ^ static_cast<std::uint64_t>(c(p.y)) * 19349663ull ^
                      static_cast<std::uint64_t>(c(p.z)) * 83492791ull;
    return k;
  };
  struct Entry {
    std::uint32_t leaf;
    Vec3 pos;
  };
  std::unordered_map<std::uint64_t, std::vector<Entry>> at;
  for (std::uint32_t i = 0; i < s.elements.size(); ++i) {
    const auto& e = s.elements[i];
    if (!e.leaf()) continue;
    for (int k = 0; k < e.poly.n; ++k) at[key(e.poly.v[k])].push_back({i, e.poly.v[k]});
  }
  const double cosMax = std::cos(30.0 * kPi / 180.0);
  s.cornerRadiosity.assign(s.elements.size(), {});
  const std::vector<char> hidden = hiddenLeaves(s);
  // The leaves a corner of leaf i averages (see the file's comment), visited with f(leaf).
  auto forEachShared = [&](std::uint32_t i, int k, auto&& f) {
    const auto& e = s.elements[i];
    const Patch& pe = s.patches[e.patch];
    for (const Entry& en : at.find(key(e.poly.v[k]))->second) {
      const auto& o = s.elements[en.leaf];
      const Patch& po = s.patches[o.patch];
      if (glm::length(en.pos - e.poly.v[k]) > 2.0 * q) continue;  // hash collision
      if (glm::dot(po.normal, pe.normal) < cosMax) continue;
      if (po.object != pe.object || po.material != pe.material) continue;
      if (hidden[en.leaf] && !hidden[i]) continue;
      f(en.leaf);
    }
  };
  // Each leaf's corners read the map and write their own entries: in parallel, in a fixed order.
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, std::uint32_t(s.elements.size()), 256), [&](const auto& r) {
    for (std::uint32_t i = r.begin(); i != r.end(); ++i) {
      const auto& e = s.elements[i];
      if (!e.leaf()) continue;
      for (int k = 0; k < e.poly.n; ++k) {
        Rgb sum(0.0);
        double w = 0.0;
        forEachShared(i, k, [&](std::uint32_t j) {
          double a = s.elements[j].poly.area();
          sum += a * s.elements[j].radiosity;
          w += a;
        });
        s.cornerRadiosity[i][k] = w > 0.0 ? sum / w : e.radiosity;
      }
    }
  });
  // The mean passes (the file's comment): each moves every corner by the area-weighted mean of its
  // leaves' shortfalls (for a quadratic falloff on even leaves one pass makes every drawn mean
  // exact), kept within the range of those leaves' radiosity so that a shadow edge, where the
  // shortfalls alternate, does not ring.
  std::vector<Rgb> shortfall(s.elements.size());
  for (int pass = 0; pass < kMeanPasses; ++pass) {
    tbb::parallel_for(std::uint32_t(0), std::uint32_t(s.elements.size()), [&](std::uint32_t i) {
      const auto& e = s.elements[i];
      if (!e.leaf()) return;
      shortfall[i] = e.radiosity - drawnMean(s, i, s.cornerRadiosity[i]);
    });
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, std::uint32_t(s.elements.size()), 256), [&](const auto& r) {
      for (std::uint32_t i = r.begin(); i != r.end(); ++i) {
        const auto& e = s.elements[i];
        if (!e.leaf()) continue;
        for (int k = 0; k < e.poly.n; ++k) {
          Rgb sum(0.0), lo(1e300), hi(-1e300);
          double w = 0.0;
          forEachShared(i, k, [&](std::uint32_t j) {
            double a = s.elements[j].poly.area();
            sum += a * shortfall[j];
            w += a;
            lo = glm::min(lo, s.elements[j].radiosity), hi = glm::max(hi, s.elements[j].radiosity);
          });
          if (w > 0.0) s.cornerRadiosity[i][k] = glm::clamp(s.cornerRadiosity[i][k] + sum / w, lo, hi);
        }
      }
    });
  }
}

std::string encodeDisplayCorners(const std::vector<std::array<Rgb, 4>>& corners) {
  std::string out(kDisplayCorners);
  const std::size_t head = out.size();
  out.resize(head + corners.size() * 12 * sizeof(double));
  char* p = out.data() + head;
  for (const auto& c : corners)
    for (const Rgb& v : c)
      for (int k = 0; k < 3; ++k, p += sizeof(double)) std::memcpy(p, &v[k], sizeof(double));
  return out;
}

std::vector<std::array<Rgb, 4>> decodeDisplayCorners(const Solution& s, const std::string& payload) {
  const std::size_t head = std::strlen(kDisplayCorners);
  if (payload.size() != head + s.elements.size() * 12 * sizeof(double))
    throw InputError("section \"display\": " + std::to_string(payload.size() - head) + " bytes of corners for " +
                     std::to_string(s.elements.size()) + " elements (12 doubles each)");
  std::vector<std::array<Rgb, 4>> corners(s.elements.size());
  const char* p = payload.data() + head;
  for (auto& c : corners)
    for (Rgb& v : c)
      for (int k = 0; k < 3; ++k, p += sizeof(double)) {
        double x;
        std::memcpy(&x, p, sizeof(double));
        if (!std::isfinite(x) || x < 0.0 || x > 1e30)
          throw InputError("section \"display\": corner radiosity " + std::to_string(x) + " outside [0, 1e30]");
        v[k] = x;
      }
  return corners;
}

Vec3 surfaceNormal(const Solution& s, std::uint32_t patch, const Vec3& x) {
  if (s.surfaces.empty()) return Vec3(0.0);
  const Patch& p = s.patches[patch];
  const Vec3 n = s.surfaces[p.object].normalAt(x);
  return glm::dot(n, p.normal) < 0.0 ? -n : n;
}

Rgb interpolate(const Solution& s, std::uint32_t leaf, const Vec3& x) {
  return interpolateCorners(s, leaf, x, s.cornerRadiosity[leaf]);
}

std::array<double, 4> cornerWeights(const Solution& s, std::uint32_t leaf, const Vec3& x) {
  const auto& e = s.elements[leaf];
  const Vec3& n = s.patches[e.patch].normal;
  auto bary = [&](const Vec3& a, const Vec3& b, const Vec3& c, double& u, double& v, double& w) {
    double area = glm::dot(glm::cross(b - a, c - a), n);
    if (std::abs(area) < 1e-300) {
      u = v = w = 1.0 / 3.0;
      return;
    }
    u = glm::dot(glm::cross(b - x, c - x), n) / area;
    v = glm::dot(glm::cross(c - x, a - x), n) / area;
    w = 1.0 - u - v;
  };
  double u, v, w;
  if (e.poly.n == 3) {
    bary(e.poly.v[0], e.poly.v[1], e.poly.v[2], u, v, w);
    u = glm::clamp(u, 0.0, 1.0), v = glm::clamp(v, 0.0, 1.0), w = glm::clamp(w, 0.0, 1.0);
    double t = std::max(u + v + w, 1e-300);
    return {u / t, v / t, w / t, 0.0};
  }
  // Quads: four triangles around the centre, whose value is the mean of the corners.
  Vec3 c = e.poly.centroid();
  for (int k = 0; k < 4; ++k) {
    bary(e.poly.v[k], e.poly.v[(k + 1) % 4], c, u, v, w);
    if ((u >= -1e-9 && v >= -1e-9 && w >= -1e-9) || k == 3) {
      u = glm::clamp(u, 0.0, 1.0), v = glm::clamp(v, 0.0, 1.0), w = glm::clamp(w, 0.0, 1.0);
      double t = std::max(u + v + w, 1e-300);
      std::array<double, 4> out;
      out.fill(0.25 * w / t);
      out[std::size_t(k)] += u / t;
      out[std::size_t((k + 1) % 4)] += v / t;
      return out;
    }
  }
  return {0.25, 0.25, 0.25, 0.25};
}

Rgb interpolateCorners(const Solution& s, std::uint32_t leaf, const Vec3& x, const std::array<Rgb, 4>& cv) {
  const std::array<double, 4> w = cornerWeights(s, leaf, x);
  return w[0] * cv[0] + w[1] * cv[1] + w[2] * cv[2] + w[3] * cv[3];
}

}  // namespace hr
