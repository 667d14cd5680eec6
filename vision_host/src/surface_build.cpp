// Scene objects to whole surfaces (the VISION-like host's initial patches): nothing is tessellated.
// A box gives its six faces, a mesh its faces; a polygon stays one surface when it is star-shaped
// about its area centroid (every convex polygon is), else it is triangulated (the only split, and
// counted). A quad that is not planar becomes two triangles, as on the tessellating host.
#include <hr/curved_surface.h>
#include <hr/geometry.h>
#include <hr/limits.h>
#include <vision/surface.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace vision {

using hr::kPi;

Surface Surface::bilinear(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  Surface s;
  s.kind = SurfaceKind::Bilinear;
  s.pts = {a, b, c, d};
  Vec3 n = glm::cross(c - a, d - b);  // a quad's area vector, twice; a triangle's too (d == c)
  s.flatNormal = glm::normalize(n);
  return s;
}

bool Surface::star(const std::vector<Vec3>& p, Surface& out) {
  const std::size_t n = p.size();
  Vec3 nrm(0.0);
  for (std::size_t i = 0; i < n; ++i) nrm += glm::cross(p[i], p[(i + 1) % n]);
  double twiceArea = glm::length(nrm);
  if (!(twiceArea > 0.0)) return false;
  nrm /= twiceArea;
  // Area centroid from a fan about the first vertex.
  Vec3 c(0.0);
  double total = 0.0;
  for (std::size_t i = 1; i + 1 < n; ++i) {
    double a = glm::dot(glm::cross(p[i] - p[0], p[i + 1] - p[0]), nrm);
    c += a * (p[0] + p[i] + p[i + 1]) / 3.0;
    total += a;
  }
  if (!(total > 0.0)) return false;
  c /= total;
  // Star-shaped about c: every sector (c, p_i, p_i+1) turns the same way and is not a sliver.
  Surface s;
  s.kind = SurfaceKind::Star;
  s.pts.push_back(c);
  s.pts.insert(s.pts.end(), p.begin(), p.end());
  s.flatNormal = nrm;
  s.breaks_.push_back(0.0);
  double acc = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    double a = glm::dot(glm::cross(p[i] - c, p[(i + 1) % n] - c), nrm);
    if (!(a > 1e-9 * total)) return false;
    acc += a;
    s.breaks_.push_back(acc);
  }
  for (double& b : s.breaks_) b /= acc;
  s.breaks_.back() = 1.0;
  s.r0 = 0.5 * acc;  // the polygon's area: the star map's constant Jacobian
  out = s;
  return true;
}

Surface Surface::annulus(const glm::dmat4& toWorld, double rInner, double rOuter) {
  Surface s;
  s.kind = SurfaceKind::Annulus;
  s.r0 = rInner, s.r1 = rOuter;
  s.setFrame(toWorld);
  return s;
}

Surface Surface::sphere(const glm::dmat4& toWorld, double radius) {
  Surface s;
  s.kind = SurfaceKind::Sphere;
  s.r0 = radius;
  s.setFrame(toWorld);
  return s;
}

Surface Surface::frustum(const glm::dmat4& toWorld, double rBase, double rTop, double h) {
  Surface s;
  s.kind = SurfaceKind::Frustum;
  s.r0 = rBase, s.r1 = rTop, s.height = h;
  s.setFrame(toWorld);
  return s;
}

namespace {

class Sink {
 public:
  Sink(std::vector<Surface>& out, SurfaceReport& rep) : out_(out), rep_(rep) {}
  void setOwner(std::uint32_t material, std::uint32_t object) { mat_ = material, obj_ = object; }

  /// A planar polygon given in world space, counter-clockwise about its front.
  void polygon(std::vector<Vec3> p) {
    std::vector<Vec3> q;
    for (const Vec3& v : p)
      if (q.empty() || glm::length(v - q.back()) > 0.0) q.push_back(v);
    while (q.size() > 1 && glm::length(q.front() - q.back()) == 0.0) q.pop_back();
    if (q.size() < 3) return drop();
    if (q.size() == 3) return add(Surface::bilinear(q[0], q[1], q[2], q[2]), q);
    if (q.size() == 4 && convexPlanar(q)) return add(Surface::bilinear(q[0], q[1], q[2], q[3]), q);
    if (q.size() == 4 && !planar(q)) {
      ++rep_.nonPlanarQuads;
      polygon({q[0], q[1], q[2]});
      polygon({q[0], q[2], q[3]});
      return;
    }
    Surface s;
    if (Surface::star(q, s)) return add(s, q);
    std::vector<hr::Polygon> tris = hr::triangulate(q);
    rep_.split += tris.empty() ? 0 : tris.size() - 1;
    for (const hr::Polygon& t : tris) polygon({t.v[0], t.v[1], t.v[2]});
  }

  void quadric(Surface s) {
    s.material = mat_, s.object = obj_;
    double area = 0.0;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) area += s.jacobian((i + 0.5) / 4, (j + 0.5) / 4) / 16.0;
    if (!(area > 0.0) || !std::isfinite(area)) return drop();
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; j <= 8; ++j) check(s.point(i / 8.0, j / 8.0));
    out_.push_back(std::move(s));
  }

 private:
  static bool planar(const std::vector<Vec3>& q) {
    Vec3 n = glm::cross(q[2] - q[0], q[3] - q[1]);
    double len = glm::length(n), size = glm::length(q[2] - q[0]) + glm::length(q[3] - q[1]);
    return len > 0.0 && std::abs(glm::dot(n / len, q[3] - q[0])) <= 1e-6 * size;
  }
  static bool convexPlanar(const std::vector<Vec3>& q) {
    if (!planar(q)) return false;
    Vec3 n = glm::cross(q[2] - q[0], q[3] - q[1]);
    for (int i = 0; i < 4; ++i)
      if (glm::dot(glm::cross(q[(i + 1) % 4] - q[i], q[(i + 2) % 4] - q[(i + 1) % 4]), n) <= 0.0) return false;
    return true;
  }
  void add(Surface s, const std::vector<Vec3>& q) {
    Vec3 a(0.0);
    double r = 0.0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      a += glm::cross(q[i], q[(i + 1) % q.size()]);
      r = std::max(r, glm::length(q[i] - q[0]));
    }
    // Degenerate like the tessellating host's: area negligible against the extent squared.
    if (!(0.5 * glm::length(a) > 1e-12 * r * r)) return drop();
    for (const Vec3& v : q) check(v);
    s.material = mat_, s.object = obj_;
    out_.push_back(std::move(s));
  }
  void drop() { ++rep_.dropped; }
  void check(const Vec3& v) const {
    for (int c = 0; c < 3; ++c)
      if (!hr::limits::within(v[c], hr::limits::kCoordinate))
        throw hr::InputError("object " + std::to_string(obj_) + ": a point lands at coordinate " + std::to_string(v[c]) +
                             " after the transform, outside the allowed range " + hr::limits::kCoordinate.text() + " m");
  }
  std::vector<Surface>& out_;
  SurfaceReport& rep_;
  std::uint32_t mat_ = 0, obj_ = 0;
};

/// A mesh file's faces, with its materials appended to the scene under "file:name".
void meshSurfaces(hr::Scene& scene, const hr::Object& o, std::uint32_t mat, const glm::dmat4& xf, bool mirrored,
                  Sink& sink, std::uint32_t oi) {
  hr::MeshData md;
  try {
    md = hr::readMeshFile(o.file);
  } catch (const hr::InputError& e) {
    throw hr::InputError(o.where + ": " + e.what());
  }
  std::vector<std::uint32_t> slot;
  for (hr::Material m : md.materials) {
    m.name = o.file + ":" + m.name;
    auto it = scene.materialIndex.try_emplace(m.name, std::uint32_t(scene.materials.size())).first;
    if (it->second == scene.materials.size()) scene.materials.push_back(m);
    slot.push_back(it->second);
  }
  for (const hr::MeshFace& f : md.faces) {
    std::uint32_t fm = mat != hr::kNone ? mat : f.materialSlot >= 0 ? slot[std::size_t(f.materialSlot)] : hr::kNone;
    if (fm == hr::kNone) throw hr::InputError(o.where + ": mesh \"" + o.file + "\" has faces without a material and the object names none");
    std::vector<Vec3> p;
    for (int i = 0; i < f.poly.n; ++i) p.push_back(Vec3(xf * glm::dvec4(f.poly.v[i], 1.0)));
    if (mirrored) std::reverse(p.begin(), p.end());
    sink.setOwner(fm, oi);
    sink.polygon(p);
  }
}

}  // namespace

std::vector<Surface> buildSurfaces(hr::Scene& scene, SurfaceReport& report) {
  std::vector<Surface> out;
  Sink sink(out, report);
  for (std::uint32_t oi = 0; oi < scene.objects.size(); ++oi) {
    const hr::Object& o = scene.objects[oi];
    ++report.objects;
    const glm::dmat4 xf = o.transform.matrix();
    const bool mirrored = glm::determinant(glm::dmat3(xf)) < 0.0;
    const std::uint32_t mat = o.material.empty() ? hr::kNone : scene.materialIndex.at(o.material);
    if (mat == hr::kNone && o.type != hr::PrimitiveType::Mesh) throw std::logic_error(o.where + ": object without a material");
    sink.setOwner(mat, oi);
    auto world = [&](std::vector<Vec3> p) {
      for (Vec3& v : p) v = Vec3(xf * glm::dvec4(v, 1.0));
      if (mirrored) std::reverse(p.begin(), p.end());
      return p;
    };
    const std::size_t before = out.size();
    switch (o.type) {
      case hr::PrimitiveType::Mesh: meshSurfaces(scene, o, mat, xf, mirrored, sink, oi); continue;
      case hr::PrimitiveType::Polygon: sink.polygon(world(o.points)); break;
      case hr::PrimitiveType::Quad: sink.polygon(world({o.quad.begin(), o.quad.end()})); break;
      case hr::PrimitiveType::Box: {
        Vec3 c[8];
        for (int i = 0; i < 8; ++i) c[i] = {(i & 1) ? o.max.x : o.min.x, (i & 2) ? o.max.y : o.min.y, (i & 4) ? o.max.z : o.min.z};
        // Outward counter-clockwise faces -x, +x, -y, +y, -z, +z (the tessellating host's order).
        const int f[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
        for (const auto& q : f) {
          std::vector<Vec3> p = {c[q[0]], c[q[1]], c[q[2]], c[q[3]]};
          if (o.inward) std::reverse(p.begin(), p.end());
          sink.polygon(world(p));
        }
        break;
      }
      case hr::PrimitiveType::Disk: sink.quadric(Surface::annulus(xf * hr::frameAt(o.center, o.normal), 0.0, o.radius)); break;
      case hr::PrimitiveType::Ring: sink.quadric(Surface::annulus(xf * hr::frameAt(o.center, o.normal), o.radius, o.radius2)); break;
      case hr::PrimitiveType::Sphere: {
        Surface s = Surface::sphere(xf * glm::translate(glm::dmat4(1.0), o.center), o.radius);
        s.inward = o.inward;
        sink.quadric(s);
        break;
      }
      case hr::PrimitiveType::Cylinder:
      case hr::PrimitiveType::Cone: {
        double top = o.type == hr::PrimitiveType::Cylinder ? o.radius : o.radius2;
        Surface s = Surface::frustum(xf * hr::frameAt(o.base, o.axis), o.radius, top, o.height);
        s.inward = o.inward;
        sink.quadric(s);
        break;
      }
    }
    if (out.size() == before) throw hr::InputError(o.where + ": zero area after the transform (zero-size primitive)");
  }
  if (out.size() > hr::limits::kMaxPatches)
    throw hr::InputError("the scene has more than " + std::to_string(hr::limits::kMaxPatches) + " surfaces (the documented limit)");
  bool emits = false;
  for (const Surface& s : out) emits = emits || scene.materials[s.material].emitter();
  if (!emits)
    throw hr::InputError((scene.path.empty() ? std::string("<scene>") : scene.path) +
                         ": the scene has no emitting surface (give a material an \"emission\")");
  return out;
}

}  // namespace vision
