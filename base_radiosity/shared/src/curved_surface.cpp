// Exact normals of curved primitives at points, and their ".ghrs" section (see curved_surface.h).
// The normal is computed in the quadric's own frame and carried out by the inverse transpose.
#include <hr/curved_surface.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace hr {

void CurvedSurface::setFrame(const glm::dmat4& m) {
  toWorld = m;
  toLocal = glm::inverse(m);
  normalToWorld = glm::transpose(glm::inverse(glm::dmat3(m)));
}

Vec3 CurvedSurface::normalAt(const Vec3& p) const {
  const Vec3 q(toLocal * glm::dvec4(p, 1.0));
  Vec3 n(0.0);
  if (kind == CurvedKind::Sphere) {
    n = q;
  } else if (kind == CurvedKind::Frustum) {
    const double rho = std::hypot(q.x, q.y);
    if (!(rho > 1e-12 * std::max({r0, r1, height}))) return Vec3(0.0);
    // The side's normal: radial, tilted toward the narrower end by the slope (r0 - r1) / height.
    n = Vec3(height * q.x / rho, height * q.y / rho, r0 - r1);
  }
  n = normalToWorld * n;
  const double len = glm::length(n);
  if (!(len > 0.0) || !std::isfinite(len)) return Vec3(0.0);
  return (inward ? -1.0 : 1.0) * n / len;
}

Vec3 CurvedSurface::meet(const Vec3& p, const Vec3& dir) const {
  if (kind == CurvedKind::None) return p;
  const Vec3 o(toLocal * glm::dvec4(p, 1.0)), d(toLocal * glm::dvec4(dir, 0.0));
  // The quadric along o + t d as a t^2 + b t + c = 0 (t in world units: the map is affine).
  double a, b, c;
  if (kind == CurvedKind::Sphere) {
    a = glm::dot(d, d), b = 2.0 * glm::dot(o, d), c = glm::dot(o, o) - r0 * r0;
  } else {
    const double k = height > 0.0 ? (r1 - r0) / height : 0.0, r = r0 + k * o.z;
    a = d.x * d.x + d.y * d.y - k * k * d.z * d.z;
    b = 2.0 * (o.x * d.x + o.y * d.y - k * d.z * r);
    c = o.x * o.x + o.y * o.y - r * r;
  }
  const double disc = b * b - 4.0 * a * c;
  if (!(std::abs(a) > 0.0) || !(disc >= 0.0)) return p;
  // The root furthest along dir: the first the viewer's ray meets coming from that side.
  const double s = std::sqrt(disc), t = std::max((-b - s) / (2.0 * a), (-b + s) / (2.0 * a));
  const Vec3 q = p + t * dir;
  return allFinite(q) ? q : p;
}

glm::dmat4 frameAt(const Vec3& origin, const Vec3& axis) {
  const Vec3 w = glm::normalize(axis);
  const Vec3 a = std::abs(w.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  const Vec3 u = glm::normalize(glm::cross(a, w)), v = glm::cross(w, u);
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(u, 0.0), m[1] = glm::dvec4(v, 0.0), m[2] = glm::dvec4(w, 0.0), m[3] = glm::dvec4(origin, 1.0);
  return m;
}

std::vector<CurvedSurface> curvedSurfaces(const Scene& scene) {
  std::vector<CurvedSurface> out(scene.objects.size());
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    CurvedSurface& c = out[i];
    const glm::dmat4 xf = o.transform.matrix();
    c.inward = o.inward;
    if (o.type == PrimitiveType::Sphere) {
      c.kind = CurvedKind::Sphere;
      c.setFrame(xf * glm::translate(glm::dmat4(1.0), o.center));
      c.r0 = c.r1 = o.radius;
    } else if (o.type == PrimitiveType::Cylinder || o.type == PrimitiveType::Cone) {
      c.kind = CurvedKind::Frustum;
      c.setFrame(xf * frameAt(o.base, o.axis));
      c.r0 = o.radius;
      c.r1 = o.type == PrimitiveType::Cylinder ? o.radius : o.radius2;
      c.height = o.height;
    }
  }
  return out;
}

bool anyCurved(const std::vector<CurvedSurface>& surfaces) {
  for (const CurvedSurface& c : surfaces)
    if (c.kind != CurvedKind::None) return true;
  return false;
}

namespace {

template <class T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

class Reader {
 public:
  explicit Reader(const std::string& b) : b_(b), at_(std::strlen(kSurfaces)) {}
  template <class T>
  T get() {
    if (b_.size() - at_ < sizeof(T)) fail("truncated");
    T v;
    std::memcpy(&v, b_.data() + at_, sizeof v);
    at_ += sizeof v;
    return v;
  }
  double finite() {
    const double v = get<double>();
    if (!std::isfinite(v)) fail("a value is not finite");
    return v;
  }
  bool done() const { return at_ == b_.size(); }
  [[noreturn]] static void fail(const std::string& why) { throw InputError(std::string("section \"") + kSurfaces + "\": " + why); }

 private:
  const std::string& b_;
  std::size_t at_;
};

}  // namespace

std::string encodeSurfaces(const std::vector<CurvedSurface>& surfaces) {
  std::string out(kSurfaces);
  put(out, static_cast<std::uint32_t>(surfaces.size()));
  for (const CurvedSurface& c : surfaces) {
    put(out, static_cast<std::uint8_t>(c.kind));
    if (c.kind == CurvedKind::None) continue;
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row) put(out, c.toWorld[col][row]);
    put(out, c.r0), put(out, c.r1), put(out, c.height);
    put(out, static_cast<std::uint8_t>(c.inward ? 1 : 0));
  }
  return out;
}

std::vector<CurvedSurface> decodeSurfaces(const std::string& payload, std::uint32_t objectCount) {
  if (payload.rfind(kSurfaces, 0) != 0) Reader::fail("does not begin with its name");
  Reader r(payload);
  const std::uint32_t n = r.get<std::uint32_t>();
  if (n != objectCount)
    Reader::fail(std::to_string(n) + " entries for " + std::to_string(objectCount) + " objects");
  std::vector<CurvedSurface> out(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    CurvedSurface& c = out[i];
    const std::uint8_t kind = r.get<std::uint8_t>();
    if (kind > static_cast<std::uint8_t>(CurvedKind::Frustum)) Reader::fail("entry " + std::to_string(i) + ": unknown kind " + std::to_string(kind));
    c.kind = static_cast<CurvedKind>(kind);
    if (c.kind == CurvedKind::None) continue;
    glm::dmat4 m;
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row) m[col][row] = r.finite();
    c.r0 = r.finite(), c.r1 = r.finite(), c.height = r.finite();
    const std::uint8_t inward = r.get<std::uint8_t>();
    const double det = glm::determinant(glm::dmat3(m));
    const bool sphere = c.kind == CurvedKind::Sphere;
    if (inward > 1 || !std::isfinite(det) || !(std::abs(det) > 1e-30) ||
        (sphere ? !(c.r0 > 0.0) : !(c.height > 0.0) || c.r0 < 0.0 || c.r1 < 0.0 || !(c.r0 + c.r1 > 0.0)))
      Reader::fail("entry " + std::to_string(i) + ": not a valid " + (sphere ? "sphere" : "frustum"));
    c.inward = inward == 1;
    c.setFrame(m);
  }
  if (!r.done()) Reader::fail("bytes after the last entry");
  return out;
}

}  // namespace hr
