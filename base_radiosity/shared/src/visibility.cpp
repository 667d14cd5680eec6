// Embree 3 visibility. One triangle geometry holds every patch (quads as two triangles); primIDs map
// back to patches. Errors from Embree go through the registered callback and become exceptions.
#include <embree3/rtcore.h>
#include <hr/visibility.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace hr {
namespace {

void onEmbreeError(void* user, RTCError code, const char* msg) {
  auto* last = static_cast<std::string*>(user);
  *last = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (msg ? msg : "");
  std::fprintf(stderr, "%s\n", last->c_str());
}

/// An intersect context that carries the patch a ray leaves, for the filter below.
struct FromContext {
  RTCIntersectContext ctx;
  const std::uint32_t* triToPatch;
  const Vec3* normals;
  std::uint32_t from;
  float nearCut;  // coplanar hits closer than this are ignored
};

void ignoreOrigin(const RTCFilterFunctionNArguments* args) {
  const auto* c = reinterpret_cast<const FromContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    std::uint32_t p = c->triToPatch[RTCHitN_primID(args->hit, args->N, i)];
    if (p == c->from) {
      args->valid[i] = 0;
      continue;
    }
    float t = RTCRayN_tfar(args->ray, args->N, i);
    if (t < c->nearCut && glm::dot(c->normals[p], c->normals[c->from]) > 1.0 - 1e-9) args->valid[i] = 0;
  }
}

}  // namespace

struct Visibility::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<std::uint32_t> triToPatch;
  std::vector<Vec3> normals;
  std::unique_ptr<CoplanarCover> cover;
  std::string lastError;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
  void check(const char* where) const {
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE || !lastError.empty())
      throw std::runtime_error(std::string(where) + ": " + lastError);
  }
};

Visibility::Visibility(const std::vector<Patch>& patches) : impl_(std::make_unique<Impl>()) {
  // No "threads=" setting: Embree would install a process-wide TBB limit with it and silently
  // serialise the whole program (the solver ran on one core whatever --threads said).
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw std::runtime_error("cannot create Embree device");
  rtcSetDeviceErrorFunction(impl_->device, onEmbreeError, &impl_->lastError);
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  Aabb box;
  std::size_t tris = 0;
  for (const Patch& p : patches) {
    tris += p.poly.n - 2;
    for (int k = 0; k < p.poly.n; ++k) box.grow(p.poly.v[k]);
  }
  eps_ = glm::max(1e-5 * box.diagonal(), 1e-30);
  impl_->cover = std::make_unique<CoplanarCover>(patches, eps_);
  for (const Patch& p : patches) impl_->normals.push_back(p.normal);
  RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), tris * 3));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(unsigned), tris));
  std::size_t t = 0;
  impl_->triToPatch.reserve(tris);
  for (std::uint32_t pi = 0; pi < patches.size(); ++pi) {
    const Polygon& poly = patches[pi].poly;
    for (int k = 1; k + 1 < poly.n; ++k, ++t) {
      const Vec3* v[3] = {&poly.v[0], &poly.v[k], &poly.v[k + 1]};
      for (int j = 0; j < 3; ++j) {
        vb[9 * t + 3 * j + 0] = static_cast<float>(v[j]->x);
        vb[9 * t + 3 * j + 1] = static_cast<float>(v[j]->y);
        vb[9 * t + 3 * j + 2] = static_cast<float>(v[j]->z);
        ib[3 * t + j] = static_cast<unsigned>(3 * t + j);
      }
      impl_->triToPatch.push_back(pi);
    }
  }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(impl_->scene, geom);
  rtcReleaseGeometry(geom);
  // The BVH is built on one thread so that it, and every ray's answer at ties, is the same whatever
  // the thread count; the build is a few ms against seconds of ray queries.
  tbb::task_arena serialBuild(1);
  serialBuild.execute([&] { rtcCommitScene(impl_->scene); });
  impl_->check("building the Embree scene");
}

Visibility::~Visibility() = default;

void* Visibility::rawScene() const { return impl_->scene; }

void Visibility::occluded(const Vec3* from, const Vec3* to, int count, bool* blocked) const {
  RTCIntersectContext ctx;
  for (int base = 0; base < count; base += 16) {
    int n = glm::min(16, count - base);
    alignas(64) RTCRay16 r;
    alignas(64) int valid[16];
    for (int i = 0; i < 16; ++i) {
      valid[i] = i < n ? -1 : 0;
      Vec3 o = i < n ? from[base + i] : Vec3(0.0), d = i < n ? to[base + i] - o : Vec3(0, 0, 1);
      double len = glm::length(d);
      bool ok = i < n && len > 2.0 * eps_;
      if (i < n && !ok) valid[i] = 0;
      r.org_x[i] = static_cast<float>(o.x);
      r.org_y[i] = static_cast<float>(o.y);
      r.org_z[i] = static_cast<float>(o.z);
      r.dir_x[i] = static_cast<float>(d.x);
      r.dir_y[i] = static_cast<float>(d.y);
      r.dir_z[i] = static_cast<float>(d.z);
      r.tnear[i] = ok ? static_cast<float>(eps_ / len) : 0.0f;
      r.tfar[i] = ok ? static_cast<float>(1.0 - eps_ / len) : 0.0f;
      r.time[i] = 0.0f;
      r.mask[i] = 0xFFFFFFFFu;
      r.id[i] = 0;
      r.flags[i] = 0;
    }
    rtcInitIntersectContext(&ctx);
    rtcOccluded16(valid, impl_->scene, &ctx, &r);
    // Segments shorter than twice the trimming distance touch: nothing fits between their ends.
    for (int i = 0; i < n; ++i) blocked[base + i] = valid[i] && r.tfar[i] < 0.0f;
  }
}

bool Visibility::occluded(const Vec3& from, const Vec3& to) const {
  bool b = false;
  occluded(&from, &to, 1, &b);
  return b;
}

bool Visibility::escapes(const Vec3& org, const Vec3& dir) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  r.org_x = static_cast<float>(org.x);
  r.org_y = static_cast<float>(org.y);
  r.org_z = static_cast<float>(org.z);
  r.dir_x = static_cast<float>(dir.x);
  r.dir_y = static_cast<float>(dir.y);
  r.dir_z = static_cast<float>(dir.z);
  r.tnear = static_cast<float>(eps_);
  r.tfar = std::numeric_limits<float>::infinity();
  r.time = 0.0f;
  r.mask = 0xFFFFFFFFu;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(impl_->scene, &ctx, &r);
  return r.tfar >= 0.0f;
}

std::uint32_t Visibility::coverOf(std::uint32_t p, const Vec3& x) const { return impl_->cover->coverOf(p, x); }
bool Visibility::partlyCovered(std::uint32_t p) const { return impl_->cover->covers(p); }

SurfaceHit Visibility::intersectFrom(const Vec3& org, const Vec3& dir, std::uint32_t from) const {
  FromContext c;
  rtcInitIntersectContext(&c.ctx);
  c.ctx.filter = ignoreOrigin;
  c.triToPatch = impl_->triToPatch.data();
  c.normals = impl_->normals.data();
  c.from = from;
  c.nearCut = static_cast<float>(eps_ / std::max(glm::length(dir), 1e-300));
  return trace(org, dir, &c.ctx);
}

SurfaceHit Visibility::intersect(const Vec3& org, const Vec3& dir) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  return trace(org, dir, &ctx);
}

SurfaceHit Visibility::trace(const Vec3& org, const Vec3& dir, void* context) const {
  auto* ctxp = static_cast<RTCIntersectContext*>(context);
  RTCRayHit rh;
  rh.ray.org_x = static_cast<float>(org.x);
  rh.ray.org_y = static_cast<float>(org.y);
  rh.ray.org_z = static_cast<float>(org.z);
  rh.ray.dir_x = static_cast<float>(dir.x);
  rh.ray.dir_y = static_cast<float>(dir.y);
  rh.ray.dir_z = static_cast<float>(dir.z);
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, ctxp, &rh);
  SurfaceHit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.hit = true;
  h.t = rh.ray.tfar;
  h.patch = impl_->triToPatch[rh.hit.primID];
  return h;
}

void Visibility::intersect(const Vec3* org, const Vec3* dir, int count, SurfaceHit* hits) const {
  RTCIntersectContext ctx;
  for (int base = 0; base < count; base += 16) {
    int n = glm::min(16, count - base);
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[16];
    for (int i = 0; i < 16; ++i) {
      // Idle lanes get a harmless ray: Embree reads every lane's data whatever valid says.
      Vec3 o = i < n ? org[base + i] : Vec3(0.0), d = i < n ? dir[base + i] : Vec3(0, 0, 1);
      valid[i] = i < n ? -1 : 0;
      rh.ray.org_x[i] = static_cast<float>(o.x);
      rh.ray.org_y[i] = static_cast<float>(o.y);
      rh.ray.org_z[i] = static_cast<float>(o.z);
      rh.ray.dir_x[i] = static_cast<float>(d.x);
      rh.ray.dir_y[i] = static_cast<float>(d.y);
      rh.ray.dir_z[i] = static_cast<float>(d.z);
      rh.ray.tnear[i] = 0.0f;
      rh.ray.tfar[i] = std::numeric_limits<float>::infinity();
      rh.ray.time[i] = 0.0f;
      rh.ray.mask[i] = 0xFFFFFFFFu;
      rh.ray.id[i] = 0;
      rh.ray.flags[i] = 0;
      rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcInitIntersectContext(&ctx);
    rtcIntersect16(valid, impl_->scene, &ctx, &rh);
    for (int i = 0; i < n; ++i) {
      SurfaceHit& h = hits[base + i];
      h = SurfaceHit{};
      if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
      h.hit = true;
      h.t = rh.ray.tfar[i];
      h.patch = impl_->triToPatch[rh.hit.primID[i]];
    }
  }
}

void Visibility::setRobust(bool robust) {
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | (robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE));
  // The flags pick the traversal kernels when the BVH is built; an unmodified scene is not rebuilt.
  rtcCommitGeometry(rtcGetGeometry(impl_->scene, 0));
  tbb::task_arena serialBuild(1);
  serialBuild.execute([&] { rtcCommitScene(impl_->scene); });
  impl_->check("rebuilding the Embree scene");
}

}  // namespace hr
