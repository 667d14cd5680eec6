// The estimator at one path vertex: emission with MIS against the previous light sample,
// next-event estimation of one emitter point (MIS against BRDF sampling), a BRDF-sampled
// continuation and Russian roulette. Vertices are lifted off their surface along the normal by the
// visibility epsilon before a ray leaves them (as in the solver's shadow rays).
#include <ref/cosine_sampling.h>
#include <ref/path_tracer.h>

#include <algorithm>
#include <cmath>

namespace ref {

namespace {

/// Roulette only after this many bounces: earlier vertices carry most of the image. Measured on the
/// Cornell box and the three-lights room (variance per sample x CPU time per sample): starting after
/// 1 bounce costs 27 % more variance for 25 % less time; 3, 5 and 8 are alike within the noise (10 %).
constexpr int kRouletteDepth = 3;

double powerHeuristic(double a, double b) { return a * a / (a * a + b * b); }

}  // namespace

PathTracer::PathTracer(const hr::Scene& scene, std::vector<hr::Patch> patches) : patches_(std::move(patches)) {
  vis_ = std::make_unique<hr::Visibility>(patches_);
  // Non-robust traversal: 14 % fewer instructions per path (callgrind, Cornell box); a ray that slips
  // through a shared edge is a rounding-level event, far below the noise (the furnace test, a closed
  // cube where any leak loses energy, stays within its tolerance).
  vis_->setRobust(false);
  eps_ = vis_->epsilon();
  for (const hr::Material& m : scene.materials) {
    Surface s;
    s.brdf = glossy::ModifiedPhong{m.diffuse, m.specular, m.exponent};
    s.emission = m.emission;
    s.emits = hr::maxComponent(m.emission) > 0.0;
    s.reflects = hr::maxComponent(m.diffuse) + hr::maxComponent(m.specular) > 0.0;
    s.lambert = hr::maxComponent(m.specular) <= 0.0;
    surfaces_.push_back(s);
  }
  std::vector<double> power;
  frames_.resize(patches_.size());
  for (std::uint32_t i = 0; i < patches_.size(); ++i) {
    const hr::Patch& p = patches_[i];
    glossy::orthonormalBasis(p.normal, frames_[i].t, frames_[i].b);
    double w = hr::luminance(surfaces_[p.material].emission) * p.area;
    if (w <= 0.0) continue;
    Emitter e;
    e.patch = i;
    e.v0 = p.poly.v[0];
    e.e1 = p.poly.v[1] - e.v0;
    e.e2 = p.poly.v[2] - e.v0;
    if (p.poly.n == 4) {
      e.e3 = p.poly.v[3] - e.v0;
      double a0 = glm::length(glm::cross(e.e1, e.e2)), a1 = glm::length(glm::cross(e.e2, e.e3));
      e.split = a0 / (a0 + a1);
    }
    emitters_.push_back(e);
    power.push_back(w);
  }
  if (!power.empty()) {
    lights_ = AliasTable(power);
    for (std::size_t k = 0; k < emitters_.size(); ++k)
      frames_[emitters_[k].patch].lightDensity = lights_.pmf(std::uint32_t(k)) / patches_[emitters_[k].patch].area;
  }
}

PathTracer::~PathTracer() = default;

void PathTracer::shade(PathState& p, const hr::SurfaceHit& hit, int maxDepth) const {
  p.alive = false;
  p.shadow = false;
  if (!hit.hit) return;
  const hr::Patch& patch = patches_[hit.patch];
  const Vec3 n = patch.normal;
  if (glm::dot(n, p.dir) >= 0.0) return;  // the black back of a one-sided surface
  const Vec3 x = p.org + hit.t * p.dir;
  const Surface& s = surfaces_[patch.material];
  const Frame& fr = frames_[hit.patch];
  if (s.emits) {
    // The light sample's density in solid angle at the previous vertex: area density times t^2 / cos
    // (dir is a unit vector, so the distance is t).
    double pl = fr.lightDensity * hit.t * hit.t / -glm::dot(n, p.dir);
    double w = p.prevPdf > 0.0 ? powerHeuristic(p.prevPdf, pl) : 1.0;
    p.radiance += p.throughput * s.emission * w;
  }
  // A path has at most maxDepth scattering vertices; the emission above is the last thing it sees,
  // and no light sample is taken here since its BRDF-sampled partner could not be traced.
  if (!s.reflects || p.depth >= maxDepth) return;
  const Vec3 wo = -p.dir;
  const Vec3 lifted = x + n * eps_;
  // Next-event estimation: one emitter by power, one point uniformly on it.
  if (!lights_.empty()) {
    std::uint32_t pick = 0;
    if (emitters_.size() > 1) pick = lights_.sample(p.sampler.get1D());
    else p.sampler.skip();
    const Emitter& e = emitters_[pick];
    const hr::Patch& lp = patches_[e.patch];
    Uv u = p.sampler.get2D();
    // Uniform in area: the square-root warp on the triangle chosen in proportion to its area.
    bool first = u.u < e.split;
    double su = std::sqrt(first ? u.u / e.split : (u.u - e.split) / (1.0 - e.split));
    Vec3 y = e.v0 + (su * (1.0 - u.v)) * (first ? e.e1 : e.e2) + (su * u.v) * (first ? e.e2 : e.e3);
    Vec3 wl = y - x;
    double dist2 = glm::dot(wl, wl);
    wl /= std::sqrt(dist2);
    double cx = glm::dot(n, wl), cy = -glm::dot(lp.normal, wl);
    if (cx > 0.0 && cy > 0.0) {
      double pl = frames_[e.patch].lightDensity * dist2 / cy;
      double pb = s.lambert ? cx / glossy::kPi : glossy::pdf(s.brdf, wo, wl, n);
      Rgb f = s.lambert ? s.brdf.diffuse / glossy::kPi : glossy::eval(s.brdf, wl, wo, n);
      p.shadowRadiance = p.throughput * f * surfaces_[lp.material].emission * (cx * powerHeuristic(pl, pb) / pl);
      p.shadow = true;
      p.shadowFrom = lifted;
      p.shadowTo = y + lp.normal * eps_;
    }
  }
  // BRDF sampling (reciprocity: sampling about wo draws incident directions with f's shape).
  Vec3 next;
  if (s.lambert) {
    p.sampler.skip();  // the lobe choice's dimension: every material keeps the same layout
    next = sampleCosine(n, fr.t, fr.b, p.sampler.get2D());
    double c = glm::dot(n, next);
    if (c <= 0.0) return;
    p.throughput *= s.brdf.diffuse;
    p.prevPdf = c / glossy::kPi;
  } else {
    double u1 = p.sampler.get1D();
    Uv u = p.sampler.get2D();
    glossy::BrdfSample bs = glossy::sample(s.brdf, wo, n, u1, u.u, u.v);
    double c = glm::dot(n, bs.wo);
    if (bs.pdf <= 0.0 || c <= 0.0) return;
    p.throughput *= glossy::eval(s.brdf, bs.wo, wo, n) * (c / bs.pdf);
    p.prevPdf = bs.pdf;
    next = bs.wo;
  }
  ++p.depth;
  if (p.depth > kRouletteDepth) {
    // Survival in proportion to the throughput and never below it: a path still carrying (nearly) all
    // its weight is not gambled (a cap such as 0.95 would kill 5 % of those for nothing).
    double q = std::min(1.0, hr::maxComponent(p.throughput));
    if (p.sampler.get1D() >= q) return;
    p.throughput /= q;
  }
  p.org = lifted;
  p.dir = next;
  p.alive = true;
}

Rgb PathTracer::radiance(const Vec3& org, const Vec3& dir, hr::Rng& rng, int maxDepth) const {
  PathState p;
  p.start(org, dir, SampleStream(hr::Rng(rng.next(), 0)));
  while (p.alive) {
    shade(p, vis_->intersect(p.org, p.dir), maxDepth);
    if (p.shadow && !vis_->occluded(p.shadowFrom, p.shadowTo)) p.radiance += p.shadowRadiance;
  }
  return p.radiance;
}

}  // namespace ref
