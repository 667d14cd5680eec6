// Embree 3 over whole surfaces: geometry 0 holds triangles for the flat kinds with straight edges
// (a quad is two, a star polygon a fan about its centroid: exact), geometry 1 is user geometry for
// the quadrics. The user callbacks take each ray into the primitive's frame (the affine map keeps
// the ray parameter) and solve the quadric in double precision; a hit reports the surface's normal
// there so that the energy audit can tell a front from a black back.
#include <embree3/rtcore.h>
#include <tbb/task_arena.h>
#include <vision/curved_visibility.h>
#include <vision/hierarchy.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace vision {
namespace {

void onEmbreeError(void* user, RTCError code, const char* msg) {
  auto* last = static_cast<std::string*>(user);
  *last = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (msg ? msg : "");
  std::fprintf(stderr, "%s\n", last->c_str());
}

struct Quadrics {
  const std::vector<Surface>* surfaces = nullptr;
  std::vector<std::uint32_t> surface;  // primID -> surface
  std::vector<hr::Aabb> boxes;
};

/// Nearest t in (tnear, tfar) where the ray meets the quadric (its local frame), or -1; sets the
/// world normal of the emitting side there.
double hitQuadric(const Surface& s, const Vec3& ow, const Vec3& dw, double tnear, double tfar, Vec3& nworld) {
  const Vec3 o = Vec3(s.toLocal * glm::dvec4(ow, 1.0)), d = glm::dmat3(s.toLocal) * dw;
  double ts[2] = {-1.0, -1.0};
  int n = 0;
  auto solve = [&](double A, double B, double C) {
    if (std::abs(A) < 1e-300) {
      if (std::abs(B) > 1e-300) ts[n++] = -C / B;
      return;
    }
    double disc = B * B - 4.0 * A * C;
    if (disc < 0.0) return;
    double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));  // the stable root first
    double t0 = q / A, t1 = q != 0.0 ? C / q : t0;
    ts[n++] = std::min(t0, t1), ts[n++] = std::max(t0, t1);
  };
  double k = 0.0;
  switch (s.kind) {
    case SurfaceKind::Annulus:
      if (std::abs(d.z) > 1e-300) ts[n++] = -o.z / d.z;
      break;
    case SurfaceKind::Sphere: solve(glm::dot(d, d), 2.0 * glm::dot(o, d), glm::dot(o, o) - s.r0 * s.r0); break;
    default: {
      k = (s.r1 - s.r0) / s.height;
      double rz = s.r0 + k * o.z;
      solve(d.x * d.x + d.y * d.y - k * k * d.z * d.z, 2.0 * (o.x * d.x + o.y * d.y - k * d.z * rz),
            o.x * o.x + o.y * o.y - rz * rz);
    }
  }
  for (int i = 0; i < n; ++i) {
    double t = ts[i];
    if (!(t > tnear && t < tfar)) continue;
    Vec3 p = o + t * d, nl;
    if (s.kind == SurfaceKind::Annulus) {
      double r2 = p.x * p.x + p.y * p.y;
      if (r2 < s.r0 * s.r0 || r2 > s.r1 * s.r1) continue;
      nl = Vec3(0, 0, 1);
    } else if (s.kind == SurfaceKind::Sphere) {
      nl = p;
    } else {
      double rz = s.r0 + k * p.z;
      if (p.z < 0.0 || p.z > s.height || rz < 0.0) continue;  // the other nappe of the cone
      nl = Vec3(p.x, p.y, -k * rz);
    }
    nworld = s.normalMatrix * nl;
    if (s.inward) nworld = -nworld;
    return t;
  }
  return -1.0;
}

Vec3 rayOrg(RTCRayN* r, unsigned N, unsigned i) { return {RTCRayN_org_x(r, N, i), RTCRayN_org_y(r, N, i), RTCRayN_org_z(r, N, i)}; }
Vec3 rayDir(RTCRayN* r, unsigned N, unsigned i) { return {RTCRayN_dir_x(r, N, i), RTCRayN_dir_y(r, N, i), RTCRayN_dir_z(r, N, i)}; }

void quadricBounds(const RTCBoundsFunctionArguments* a) {
  const auto* q = static_cast<const Quadrics*>(a->geometryUserPtr);
  const hr::Aabb& b = q->boxes[a->primID];
  a->bounds_o->lower_x = float(b.lo.x), a->bounds_o->lower_y = float(b.lo.y), a->bounds_o->lower_z = float(b.lo.z);
  a->bounds_o->upper_x = float(b.hi.x), a->bounds_o->upper_y = float(b.hi.y), a->bounds_o->upper_z = float(b.hi.z);
}

void quadricIntersect(const RTCIntersectFunctionNArguments* a) {
  const auto* q = static_cast<const Quadrics*>(a->geometryUserPtr);
  const Surface& s = (*q->surfaces)[q->surface[a->primID]];
  RTCRayN* ray = RTCRayHitN_RayN(a->rayhit, a->N);
  RTCHitN* hit = RTCRayHitN_HitN(a->rayhit, a->N);
  for (unsigned i = 0; i < a->N; ++i) {
    if (a->valid[i] != -1) continue;
    Vec3 n;
    double t = hitQuadric(s, rayOrg(ray, a->N, i), rayDir(ray, a->N, i), RTCRayN_tnear(ray, a->N, i), RTCRayN_tfar(ray, a->N, i), n);
    if (t < 0.0) continue;
    RTCRayN_tfar(ray, a->N, i) = float(t);
    RTCHitN_Ng_x(hit, a->N, i) = float(n.x), RTCHitN_Ng_y(hit, a->N, i) = float(n.y), RTCHitN_Ng_z(hit, a->N, i) = float(n.z);
    RTCHitN_u(hit, a->N, i) = 0.0f, RTCHitN_v(hit, a->N, i) = 0.0f;
    RTCHitN_primID(hit, a->N, i) = a->primID;
    RTCHitN_geomID(hit, a->N, i) = a->geomID;
    RTCHitN_instID(hit, a->N, i, 0) = a->context->instID[0];
  }
}

void quadricOccluded(const RTCOccludedFunctionNArguments* a) {
  const auto* q = static_cast<const Quadrics*>(a->geometryUserPtr);
  const Surface& s = (*q->surfaces)[q->surface[a->primID]];
  for (unsigned i = 0; i < a->N; ++i) {
    if (a->valid[i] != -1) continue;
    Vec3 n;
    if (hitQuadric(s, rayOrg(a->ray, a->N, i), rayDir(a->ray, a->N, i), RTCRayN_tnear(a->ray, a->N, i),
                   RTCRayN_tfar(a->ray, a->N, i), n) >= 0.0)
      RTCRayN_tfar(a->ray, a->N, i) = -std::numeric_limits<float>::infinity();
  }
}

}  // namespace

struct CurvedVisibility::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  const std::vector<Surface>* surfaces = nullptr;
  std::vector<std::uint32_t> triToSurface;
  Quadrics quadrics;
  std::string lastError;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

CurvedVisibility::CurvedVisibility(const std::vector<Surface>& surfaces) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.surfaces = &surfaces;
  m.quadrics.surfaces = &surfaces;
  // No "threads=" setting: it would cap TBB process-wide (see hr/visibility.h's notes).
  m.device = rtcNewDevice(nullptr);
  if (!m.device) throw std::runtime_error("cannot create Embree device");
  rtcSetDeviceErrorFunction(m.device, onEmbreeError, &m.lastError);
  m.scene = rtcNewScene(m.device);
  rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_ROBUST);
  std::vector<Vec3> tri;
  hr::Aabb all;
  for (std::uint32_t i = 0; i < surfaces.size(); ++i) {
    const Surface& s = surfaces[i];
    hr::Aabb box = measure(s, Rect{}).box;
    all.grow(box);
    if (s.kind == SurfaceKind::Bilinear) {
      tri.insert(tri.end(), {s.pts[0], s.pts[1], s.pts[2]});
      m.triToSurface.push_back(i);
      if (glm::length(s.pts[3] - s.pts[2]) > 0.0) {
        tri.insert(tri.end(), {s.pts[0], s.pts[2], s.pts[3]});
        m.triToSurface.push_back(i);
      }
    } else if (s.kind == SurfaceKind::Star) {
      const std::size_t n = s.pts.size() - 1;
      for (std::size_t k = 0; k < n; ++k) {
        tri.insert(tri.end(), {s.pts[0], s.pts[1 + k], s.pts[1 + (k + 1) % n]});
        m.triToSurface.push_back(i);
      }
    } else {
      m.quadrics.surface.push_back(i);
      m.quadrics.boxes.push_back(box);
    }
  }
  eps_ = std::max(1e-5 * all.diagonal(), 1e-30);
  RTCGeometry g = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  const std::size_t nt = tri.size() / 3;
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), std::max<std::size_t>(tri.size(), 3)));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt));
  for (std::size_t k = 0; k < tri.size(); ++k) {
    vb[3 * k] = float(tri[k].x), vb[3 * k + 1] = float(tri[k].y), vb[3 * k + 2] = float(tri[k].z);
    ib[k] = unsigned(k);
  }
  rtcCommitGeometry(g);
  rtcAttachGeometryByID(m.scene, g, 0);
  rtcReleaseGeometry(g);
  RTCGeometry u = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(u, unsigned(m.quadrics.surface.size()));
  rtcSetGeometryUserData(u, &m.quadrics);
  rtcSetGeometryBoundsFunction(u, quadricBounds, nullptr);
  rtcSetGeometryIntersectFunction(u, quadricIntersect);
  rtcSetGeometryOccludedFunction(u, quadricOccluded);
  rtcCommitGeometry(u);
  rtcAttachGeometryByID(m.scene, u, 1);
  rtcReleaseGeometry(u);
  // Built on one thread: the BVH, and every answer at ties, is then the same whatever the threads.
  tbb::task_arena serialBuild(1);
  serialBuild.execute([&] { rtcCommitScene(m.scene); });
  if (rtcGetDeviceError(m.device) != RTC_ERROR_NONE || !m.lastError.empty())
    throw std::runtime_error("building the Embree scene: " + m.lastError);
}

CurvedVisibility::~CurvedVisibility() = default;

void CurvedVisibility::occluded(const Vec3* from, const Vec3* to, int count, bool* blocked) const {
  RTCIntersectContext ctx;
  for (int base = 0; base < count; base += 16) {
    const int n = std::min(16, count - base);
    alignas(64) RTCRay16 r;
    alignas(64) int valid[16];
    for (int i = 0; i < 16; ++i) {
      Vec3 o = i < n ? from[base + i] : Vec3(0.0), d = i < n ? to[base + i] - o : Vec3(0, 0, 1);
      double len = glm::length(d);
      bool ok = i < n && len > 2.0 * eps_;
      valid[i] = ok ? -1 : 0;
      r.org_x[i] = float(o.x), r.org_y[i] = float(o.y), r.org_z[i] = float(o.z);
      r.dir_x[i] = float(d.x), r.dir_y[i] = float(d.y), r.dir_z[i] = float(d.z);
      r.tnear[i] = ok ? float(eps_ / len) : 0.0f;
      r.tfar[i] = ok ? float(1.0 - eps_ / len) : 0.0f;
      r.time[i] = 0.0f, r.mask[i] = 0xFFFFFFFFu, r.id[i] = 0, r.flags[i] = 0;
    }
    rtcInitIntersectContext(&ctx);
    rtcOccluded16(valid, impl_->scene, &ctx, &r);
    // Ends closer than twice the trimming distance touch: nothing fits between them.
    for (int i = 0; i < n; ++i) blocked[base + i] = valid[i] && r.tfar[i] < 0.0f;
  }
}

CurvedHit CurvedVisibility::intersect(const Vec3& org, const Vec3& dir) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  rh.ray.org_x = float(org.x), rh.ray.org_y = float(org.y), rh.ray.org_z = float(org.z);
  rh.ray.dir_x = float(dir.x), rh.ray.dir_y = float(dir.y), rh.ray.dir_z = float(dir.z);
  rh.ray.tnear = float(eps_ / std::max(glm::length(dir), 1e-300));
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.time = 0.0f, rh.ray.mask = 0xFFFFFFFFu, rh.ray.id = 0, rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &ctx, &rh);
  CurvedHit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.hit = true;
  h.t = rh.ray.tfar;
  if (rh.hit.geomID == 0) {
    h.surface = impl_->triToSurface[rh.hit.primID];
    h.front = glm::dot((*impl_->surfaces)[h.surface].flatNormal, dir) < 0.0;
  } else {
    h.surface = impl_->quadrics.surface[rh.hit.primID];
    h.front = glm::dot(Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z), dir) < 0.0;
  }
  return h;
}

}  // namespace vision
