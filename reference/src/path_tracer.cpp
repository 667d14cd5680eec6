// Path tracing with next-event estimation and MIS. Vertices are lifted off their surface along the
// normal by the visibility epsilon before a ray leaves them (as in the solver's shadow rays).
#include <ref/path_tracer.h>
#include <hr/camera.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace ref {

PathTracer::PathTracer(const hr::Scene& scene, std::vector<hr::Patch> patches) : patches_(std::move(patches)) {
  vis_ = std::make_unique<hr::Visibility>(patches_);
  for (const hr::Material& m : scene.materials) {
    brdf_.push_back(glossy::ModifiedPhong{m.diffuse, m.specular, m.exponent});
    emission_.push_back(m.emission);
  }
  double total = 0.0;
  choose_.assign(patches_.size(), 0.0);
  for (std::uint32_t i = 0; i < patches_.size(); ++i) {
    double w = hr::luminance(emission_[patches_[i].material]) * patches_[i].area;
    if (w <= 0.0) continue;
    total += w;
    lights_.push_back({i, total});
    choose_[i] = w;
  }
  for (Light& l : lights_) l.cdf /= total;
  for (double& c : choose_) c /= total;
}

PathTracer::~PathTracer() = default;

double PathTracer::lightPdf(std::uint32_t patch, const Vec3& from, const Vec3& at) const {
  const hr::Patch& p = patches_[patch];
  Vec3 d = at - from;
  double d2 = glm::dot(d, d);
  double c = -glm::dot(p.normal, d / std::sqrt(d2));
  return c > 0.0 ? choose_[patch] * d2 / (p.area * c) : 0.0;
}

Rgb PathTracer::radiance(const Vec3& org, const Vec3& dir, hr::Rng& rng, int maxDepth) const {
  Rgb L(0.0), T(1.0);
  Vec3 o = org, d = dir;
  double prevPdf = 0.0;  // density of the BRDF sample that made the current ray; 0 for camera rays
  const double eps = vis_->epsilon();
  for (int depth = 0; depth < maxDepth; ++depth) {
    hr::SurfaceHit hit = vis_->intersect(o, d);
    if (!hit.hit) break;
    const hr::Patch& p = patches_[hit.patch];
    const Vec3 n = p.normal;
    if (glm::dot(n, d) >= 0.0) break;  // the black back of a one-sided surface
    const Vec3 x = o + hit.t * d;
    const Rgb& Le = emission_[p.material];
    if (hr::maxComponent(Le) > 0.0) {
      double w = 1.0;
      if (prevPdf > 0.0) {
        double pl = lightPdf(hit.patch, o, x);
        w = prevPdf * prevPdf / (prevPdf * prevPdf + pl * pl);
      }
      L += T * Le * w;
    }
    const glossy::ModifiedPhong& b = brdf_[p.material];
    if (hr::maxComponent(b.diffuse) + hr::maxComponent(b.specular) <= 0.0) break;
    const Vec3 wo = -d;
    const Vec3 lifted = x + n * eps;
    // Next-event estimation: one point on one emitter, chosen by power.
    if (!lights_.empty()) {
      double u = rng.uniform();
      auto it = std::lower_bound(lights_.begin(), lights_.end(), u, [](const Light& l, double v) { return l.cdf < v; });
      if (it == lights_.end()) --it;
      const hr::Patch& lp = patches_[it->patch];
      Vec3 y = lp.poly.sample(rng.uniform(), rng.uniform());
      Vec3 wl = y - x;
      double dist2 = glm::dot(wl, wl);
      wl /= std::sqrt(dist2);
      double cx = glm::dot(n, wl), cy = -glm::dot(lp.normal, wl);
      if (cx > 0.0 && cy > 0.0 && !vis_->occluded(lifted, y + lp.normal * eps)) {
        double pl = lightPdf(it->patch, x, y);
        double pb = glossy::pdf(b, wo, wl, n);
        double w = pl * pl / (pl * pl + pb * pb);
        L += T * glossy::eval(b, wl, wo, n) * emission_[lp.material] * (cx * w / pl);
      }
    }
    // BRDF sampling (reciprocity: sampling about wo draws incident directions with f's shape).
    glossy::BrdfSample s = glossy::sample(b, wo, n, rng.uniform(), rng.uniform(), rng.uniform());
    double c = glm::dot(n, s.wo);
    if (s.pdf <= 0.0 || c <= 0.0) break;
    T *= glossy::eval(b, s.wo, wo, n) * (c / s.pdf);
    prevPdf = s.pdf;
    if (depth >= 3) {
      double q = std::min(0.95, hr::maxComponent(T));
      if (rng.uniform() >= q) break;
      T /= q;
    }
    o = lifted;
    d = s.wo;
  }
  return L;
}

CameraResult PathTracer::render(const hr::Camera& cam, const Options& o, hr::Progress* progress) const {
  CameraResult r;
  const std::size_t P = std::size_t(cam.width) * cam.height;
  std::vector<double> sum(3 * P, 0.0), sum2(3 * P, 0.0), lsum(P, 0.0), lsum2(P, 0.0);
  std::vector<std::uint32_t> bad(P, 0);
  hr::CameraRays rays(cam);
  r.image.width = cam.width;
  r.image.height = cam.height;
  r.image.objectId.assign(P, hr::kNone);
  for (std::size_t i = 0; i < P; ++i) {
    int x = int(i % std::size_t(cam.width)), y = int(i / std::size_t(cam.width));
    hr::SurfaceHit h = vis_->intersect(rays.origin(), rays.dir(x + 0.5, y + 0.5));
    if (h.hit) r.image.objectId[i] = patches_[h.patch].object;
  }
  auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  int done = 0;
  while (true) {
    int pass = o.timeS > 0.0 ? o.passSpp : std::min(o.passSpp, o.spp - done);
    if (pass <= 0) break;
    tbb::parallel_for(0, cam.height, [&](int y) {
      for (int x = 0; x < cam.width; ++x) {
        std::size_t i = std::size_t(y) * cam.width + x;
        for (int s = done; s < done + pass; ++s) {
          hr::Rng rng(o.seed, i, std::uint64_t(s));
          Vec3 d = rays.dir(x + rng.uniform(), y + rng.uniform());
          Rgb L = radiance(rays.origin(), d, rng, o.maxDepth);
          if (!hr::allFinite(L)) {
            ++bad[i];
            continue;
          }
          for (int c = 0; c < 3; ++c) sum[3 * i + c] += L[c], sum2[3 * i + c] += L[c] * L[c];
          double l = hr::luminance(L);
          lsum[i] += l, lsum2[i] += l * l;
        }
      }
    });
    done += pass;
    if (progress) progress->update(o.timeS > 0.0 ? std::min(1.0, elapsed() / o.timeS) : double(done) / o.spp);
    if (o.timeS > 0.0 && elapsed() >= o.timeS) break;
  }
  r.seconds = elapsed();
  r.spp = done;
  r.paths = std::uint64_t(done) * P;
  r.image.rgb.assign(3 * P, 0.0f);
  r.variance.assign(3 * P, 0.0f);
  double mean = 0.0, varMean = 0.0;
  // A pixel's mean needs one sample, its variance two: with fewer the variance is unknown (left 0 and
  // flagged), never the image (one sample is an unbiased estimate; skipping it made spp 1 black).
  for (std::size_t i = 0; i < P; ++i) {
    double n = double(done) - bad[i];
    r.nonFinite += bad[i];
    if (n < 1.0) continue;
    if (n < 2.0) r.varianceKnown = false;
    for (int c = 0; c < 3; ++c) {
      double m = sum[3 * i + c] / n;
      r.image.rgb[3 * i + c] = static_cast<float>(m);
      if (n >= 2.0) r.variance[3 * i + c] = static_cast<float>(std::max(0.0, (sum2[3 * i + c] - n * m * m) / (n * (n - 1.0))));
    }
    double lm = lsum[i] / n;
    mean += lm;
    if (n >= 2.0) varMean += std::max(0.0, (lsum2[i] - n * lm * lm) / (n * (n - 1.0)));
  }
  r.meanLuminance = mean / double(P);
  r.relStdError = r.meanLuminance > 0.0 && r.varianceKnown ? std::sqrt(varMean) / double(P) / r.meanLuminance : 0.0;
  return r;
}

}  // namespace ref
