// Turns scene objects into root patches. Primitives are built as OpenMesh polygon meshes (shared
// vertices, consistent orientation), then each face becomes one planar patch. Non-planar quads are
// split into two triangles; zero-area faces are dropped and counted, never silently.
#include <hr/curved_surface.h>
#include <hr/geometry.h>
#include <hr/limits.h>

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace hr {
namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;

class MeshBuilder {
 public:
  PolyMesh::VertexHandle vertex(const Vec3& p) { return mesh_.add_vertex(PolyMesh::Point(p.x, p.y, p.z)); }
  void face(std::initializer_list<PolyMesh::VertexHandle> vs) {
    std::vector<PolyMesh::VertexHandle> v(vs);
    mesh_.add_face(v);
  }
  const PolyMesh& mesh() const { return mesh_; }

 private:
  PolyMesh mesh_;
};

Vec3 toVec(const PolyMesh::Point& p) { return {p[0], p[1], p[2]}; }

/// Orthonormal frame around a unit axis: hr::frameAt's, so that segment 0 lies where the VISION-like
/// host's u = 0 does.
void frame(const Vec3& w, Vec3& u, Vec3& v) {
  const glm::dmat4 m = frameAt(Vec3(0.0), w);
  u = Vec3(m[0]);
  v = Vec3(m[1]);
}

/// Factor on a round primitive's radii that gives its tessellation the area of the surface it stands
/// for. Inscribed polygons lose area (a 16-gon 2.55 % of its disk), and with it a light's power and
/// every transfer to and from the object; scaled out by this factor, the polygons straddle the true
/// outline instead (BRIGHT's vertices lie 1.3 % outside a 16-segment disk, its edges 0.6 % inside).
/// Closed forms for the meshes built below, in the object's own frame.
double areaPreservingScale(const Object& o, int seg) {
  const double n = seg, s = std::sin(kPi / n), c = std::cos(kPi / n);
  switch (o.type) {
    case PrimitiveType::Disk:
    case PrimitiveType::Ring: return std::sqrt(kPi / (n * s * c));  // (n/2) sin(2pi/n) r^2 against pi r^2
    case PrimitiveType::Cylinder:
    case PrimitiveType::Cone: {
      // Frustum of n trapezoids: n s (r0 + r1) k sqrt(h^2 + k^2 d^2 c^2) = pi (r0 + r1) sqrt(h^2 + d^2),
      // a quadratic in k^2, solved in the form that stays exact as d -> 0 (cylinder: k = pi / (n s)).
      const double a = n * s / kPi, h = o.height, d = o.radius - (o.type == PrimitiveType::Cone ? o.radius2 : o.radius);
      const double a2h2 = a * a * h * h, rhs = h * h + d * d;
      if (!(rhs > 0.0)) return 1.0;  // no extent: refused below as a zero-size primitive
      return std::sqrt(2.0 * rhs / (a2h2 + std::sqrt(a2h2 * a2h2 + 4.0 * a * a * d * d * c * c * rhs)));
    }
    case PrimitiveType::Sphere: {
      // buildSphere's bands (triangles at the poles) on the unit sphere.
      const int stacks = std::max(2, seg / 2);
      double area = 0.0;
      for (int k = 0; k < stacks; ++k) {
        const double t0 = kPi * k / stacks, t1 = kPi * (k + 1) / stacks;
        area += polygonBandArea(std::sin(t0), std::cos(t0), std::sin(t1), std::cos(t1), seg);
      }
      return std::sqrt(4.0 * kPi / area);
    }
    default: return 1.0;
  }
}

void buildDisk(MeshBuilder& b, const Object& o, int seg) {
  Vec3 w = glm::normalize(o.normal), u, v;
  frame(w, u, v);
  auto c = b.vertex(o.center);
  std::vector<PolyMesh::VertexHandle> ring;
  for (int i = 0; i < seg; ++i) {
    double t = 2.0 * kPi * i / seg;
    ring.push_back(b.vertex(o.center + o.radius * (std::cos(t) * u + std::sin(t) * v)));
  }
  for (int i = 0; i < seg; ++i) b.face({c, ring[i], ring[(i + 1) % seg]});
}

void buildSphere(MeshBuilder& b, const Object& o, int seg) {
  int stacks = std::max(2, seg / 2);
  auto at = [&](double th, double ph) {
    return o.center + o.radius * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
  };
  auto top = b.vertex(o.center + Vec3(0, 0, o.radius));
  auto bottom = b.vertex(o.center - Vec3(0, 0, o.radius));
  std::vector<std::vector<PolyMesh::VertexHandle>> rings(stacks - 1);
  for (int s = 1; s < stacks; ++s)
    for (int i = 0; i < seg; ++i) rings[s - 1].push_back(b.vertex(at(kPi * s / stacks, 2.0 * kPi * i / seg)));
  for (int i = 0; i < seg; ++i) {
    int j = (i + 1) % seg;
    if (o.inward) std::swap(i, j);  // reversed winding: the surface faces its centre
    b.face({top, rings[0][i], rings[0][j]});
    for (int s = 0; s + 1 < stacks - 1; ++s) b.face({rings[s][i], rings[s + 1][i], rings[s + 1][j], rings[s][j]});
    b.face({bottom, rings[stacks - 2][j], rings[stacks - 2][i]});
    if (o.inward) std::swap(i, j);
  }
}

/// An open cone frustum (a cylinder when both radii agree) from base to base + height * axis, radius
/// at the base and radius2 at the top; a zero radius closes it to an apex. Outward unless inward.
void buildFrustum(MeshBuilder& b, const Object& o, double r0, double r1, int seg) {
  Vec3 w = glm::normalize(o.axis), u, v;
  frame(w, u, v);
  std::vector<PolyMesh::VertexHandle> lo, hi;
  auto ring = [&](std::vector<PolyMesh::VertexHandle>& out, const Vec3& c, double r) {
    if (r == 0.0) {
      out.assign(std::size_t(seg), b.vertex(c));
      return;
    }
    for (int i = 0; i < seg; ++i) {
      double t = 2.0 * kPi * i / seg;
      out.push_back(b.vertex(c + r * (std::cos(t) * u + std::sin(t) * v)));
    }
  };
  ring(lo, o.base, r0);
  ring(hi, o.base + o.height * w, r1);
  for (int i = 0; i < seg; ++i) {
    int j = (i + 1) % seg;
    int a = o.inward ? j : i, c = o.inward ? i : j;
    if (r1 == 0.0)
      b.face({lo[a], lo[c], hi[0]});
    else if (r0 == 0.0)
      b.face({lo[0], hi[c], hi[a]});
    else
      b.face({lo[a], lo[c], hi[c], hi[a]});
  }
}

/// A flat annulus (a disk when the inner radius is 0) facing along normal.
void buildRing(MeshBuilder& b, const Object& o, int seg) {
  if (o.radius == 0.0) {
    Object d = o;
    d.radius = o.radius2;
    buildDisk(b, d, seg);
    return;
  }
  Vec3 w = glm::normalize(o.normal), u, v;
  frame(w, u, v);
  std::vector<PolyMesh::VertexHandle> in, out;
  for (int i = 0; i < seg; ++i) {
    double t = 2.0 * kPi * i / seg;
    Vec3 d = std::cos(t) * u + std::sin(t) * v;
    in.push_back(b.vertex(o.center + o.radius * d));
    out.push_back(b.vertex(o.center + o.radius2 * d));
  }
  for (int i = 0; i < seg; ++i) {
    int j = (i + 1) % seg;
    b.face({in[i], out[i], out[j], in[j]});
  }
}

void buildBox(MeshBuilder& b, const Object& o) {
  PolyMesh::VertexHandle c[8];
  for (int i = 0; i < 8; ++i)
    c[i] = b.vertex({(i & 1) ? o.max.x : o.min.x, (i & 2) ? o.max.y : o.min.y, (i & 4) ? o.max.z : o.min.z});
  // Outward counter-clockwise faces: -x, +x, -y, +y, -z, +z.
  int f[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (auto& q : f) {
    if (o.inward)
      b.face({c[q[3]], c[q[2]], c[q[1]], c[q[0]]});
    else
      b.face({c[q[0]], c[q[1]], c[q[2]], c[q[3]]});
  }
}

class PatchSink {
 public:
  PatchSink(std::vector<Patch>& out, TessellationReport& rep, double planarTol)
      : out_(out), rep_(rep), tol_(planarTol) {}

  void add(const Polygon& p, std::uint32_t material, std::uint32_t object) {
    if (p.n == 4) {
      Vec3 nrm = p.areaVector();
      double len = glm::length(nrm);
      double size = p.radius();
      if (len > 0.0 && std::abs(glm::dot(nrm / len, p.v[3] - p.v[0])) > tol_ * size) {
        ++rep_.splitNonPlanar;
        add({{p.v[0], p.v[1], p.v[2], Vec3(0.0)}, 3}, material, object);
        add({{p.v[0], p.v[2], p.v[3], Vec3(0.0)}, 3}, material, object);
        return;
      }
    }
    Vec3 a = p.areaVector();
    double area = glm::length(a);
    double r = p.radius();
    // A face is degenerate when its area is negligible against its own extent squared (slivers
    // with a true, tiny area are kept: they are valid input and the kernels stay bounded for them).
    if (!(area > 1e-12 * r * r) || !(area > 0.0)) {
      ++rep_.droppedZeroArea;
      return;
    }
    Patch pt;
    pt.poly = p;
    pt.normal = a / area;
    pt.area = area;
    pt.material = material;
    pt.object = object;
    out_.push_back(pt);
  }

 private:
  std::vector<Patch>& out_;
  TessellationReport& rep_;
  double tol_;
};

void emitMesh(const PolyMesh& m, const glm::dmat4& xf, bool mirrored, PatchSink& sink, std::uint32_t mat,
              std::uint32_t obj) {
  for (auto fh : m.faces()) {
    std::vector<Vec3> pts;
    for (auto vh : m.fv_range(fh)) pts.push_back(Vec3(xf * glm::dvec4(toVec(m.point(vh)), 1.0)));
    if (mirrored) std::reverse(pts.begin(), pts.end());
    if (pts.size() == 3 || pts.size() == 4) {
      Polygon p;
      p.n = static_cast<int>(pts.size());
      for (int i = 0; i < p.n; ++i) p.v[i] = pts[i];
      sink.add(p, mat, obj);
    }
  }
}

}  // namespace

double polygonBandArea(double r0, double z0, double r1, double z1, int n) {
  // Parallel sides 2 r sin(pi/n); height between their midpoints, at r cos(pi/n).
  const double dr = (r0 - r1) * std::cos(kPi / n), dz = z1 - z0;
  return n * std::sin(kPi / n) * (r0 + r1) * std::sqrt(dr * dr + dz * dz);
}

std::vector<Polygon> triangulate(std::vector<Vec3> pts) {
  std::vector<Polygon> out;
  // Drop consecutive duplicates (closing vertex repeated, zero-length edges).
  std::vector<Vec3> p;
  for (const Vec3& v : pts)
    if (p.empty() || glm::length(v - p.back()) > 0.0) p.push_back(v);
  while (p.size() > 1 && glm::length(p.front() - p.back()) == 0.0) p.pop_back();
  if (p.size() < 3) return out;
  Vec3 n(0.0);
  for (std::size_t i = 0; i < p.size(); ++i) n += glm::cross(p[i], p[(i + 1) % p.size()]);
  double len = glm::length(n);
  if (len == 0.0) return out;
  n /= len;
  if (p.size() == 3) return {Polygon{{p[0], p[1], p[2], Vec3(0.0)}, 3}};
  auto convexAt = [&](const Vec3& a, const Vec3& b, const Vec3& c) { return glm::dot(glm::cross(b - a, c - b), n) > 0.0; };
  if (p.size() == 4 && convexAt(p[0], p[1], p[2]) && convexAt(p[1], p[2], p[3]) && convexAt(p[2], p[3], p[0]) &&
      convexAt(p[3], p[0], p[1]))
    return {Polygon{{p[0], p[1], p[2], p[3]}, 4}};
  std::vector<std::size_t> idx(p.size());
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  auto inside = [&](const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
    // Inside or on the boundary: a reflex vertex on an ear's edge blocks it (else the ear would
    // cover a notch). Copies of the ear's own corners (a seam walks them twice) are skipped above.
    double e = -1e-12 * len;
    return glm::dot(glm::cross(b - a, q - a), n) >= e && glm::dot(glm::cross(c - b, q - b), n) >= e &&
           glm::dot(glm::cross(a - c, q - c), n) >= e;
  };
  std::size_t guard = 0;
  while (idx.size() > 3 && guard < 4 * p.size() * p.size()) {
    bool clipped = false;
    for (std::size_t k = 0; k < idx.size(); ++k, ++guard) {
      const Vec3 &a = p[idx[(k + idx.size() - 1) % idx.size()]], &b = p[idx[k]], &c = p[idx[(k + 1) % idx.size()]];
      if (!convexAt(a, b, c)) continue;
      bool ear = true;
      for (std::size_t m : idx) {
        const Vec3& q = p[m];
        if (q == a || q == b || q == c) continue;
        if (inside(q, a, b, c)) {
          ear = false;
          break;
        }
      }
      if (!ear) continue;
      out.push_back(Polygon{{a, b, c, Vec3(0.0)}, 3});
      idx.erase(idx.begin() + std::ptrdiff_t(k));
      clipped = true;
      break;
    }
    if (!clipped) break;  // degenerate remainder (collinear vertices): nothing left with area
  }
  if (idx.size() == 3) out.push_back(Polygon{{p[idx[0]], p[idx[1]], p[idx[2]], Vec3(0.0)}, 3});
  return out;
}

namespace {

/// Every vertex an object produced lies where single-precision rays still work (hr/limits.h): the
/// readers check the values they read, but transforms, MGF contexts and mesh files combine them.
void checkPlacement(const std::vector<Patch>& patches, std::size_t from, const Object& o) {
  if (patches.size() > limits::kMaxPatches)
    throw InputError(o.where + ": the scene tessellates into more than " + std::to_string(limits::kMaxPatches) +
                     " patches (the documented limit)");
  for (std::size_t i = from; i < patches.size(); ++i)
    for (int k = 0; k < patches[i].poly.n; ++k) {
      const Vec3& v = patches[i].poly.v[k];
      for (int c = 0; c < 3; ++c)
        if (!limits::within(v[c], limits::kCoordinate))
          throw InputError(o.where + ": a vertex lands at coordinate " + std::to_string(v[c]) +
                           " after the transform, outside the allowed range " + limits::kCoordinate.text() + " m");
    }
}

}  // namespace

std::vector<Patch> buildPatches(Scene& scene, TessellationReport& report) {
  std::vector<Patch> patches;
  PatchSink sink(patches, report, 1e-6);
  const int seg = scene.settings.tessellation;
  for (std::uint32_t oi = 0; oi < scene.objects.size(); ++oi) {
    const Object& o = scene.objects[oi];
    const std::size_t first = patches.size();
    glm::dmat4 xf = o.transform.matrix();
    // A mirroring transform would turn every face inside out: keep the declared facing.
    const bool mirrored = glm::determinant(glm::dmat3(xf)) < 0.0;
    std::uint32_t mat = o.material.empty() ? kNone : scene.materialIndex.at(o.material);
    // Only a mesh may leave its material to its file; anything else without one is a reader's bug.
    if (mat == kNone && o.type != PrimitiveType::Mesh) throw std::logic_error(o.where + ": object without a material");
    if (o.type == PrimitiveType::Mesh) {
      MeshData md;
      try {
        md = readMeshFile(o.file);
      } catch (const InputError& e) {
        throw InputError(o.where + ": " + e.what());
      }
      std::vector<std::uint32_t> slot(md.materials.size());
      for (std::size_t i = 0; i < md.materials.size(); ++i) {
        Material m = md.materials[i];
        m.name = o.file + ":" + m.name;
        auto it = scene.materialIndex.find(m.name);
        if (it == scene.materialIndex.end()) {
          it = scene.materialIndex.emplace(m.name, static_cast<std::uint32_t>(scene.materials.size())).first;
          scene.materials.push_back(m);
        }
        slot[i] = it->second;
      }
      for (const MeshFace& f : md.faces) {
        std::uint32_t fm = mat;  // an explicit material on the object overrides the file's
        if (fm == kNone) {
          if (f.materialSlot < 0)
            throw InputError(o.where + ": mesh \"" + o.file +
                             "\" has faces without a material and the object names none");
          fm = slot[f.materialSlot];
        }
        Polygon p = f.poly;
        for (int i = 0; i < p.n; ++i) p.v[i] = Vec3(xf * glm::dvec4(p.v[i], 1.0));
        sink.add(p, fm, oi);
      }
      checkPlacement(patches, first, o);
      continue;
    }
    if (o.type == PrimitiveType::Polygon) {
      std::vector<Vec3> pts;
      for (const Vec3& p : o.points) pts.push_back(Vec3(xf * glm::dvec4(p, 1.0)));
      if (mirrored) std::reverse(pts.begin(), pts.end());
      std::size_t before = patches.size();
      for (const Polygon& t : triangulate(pts)) sink.add(t, mat, oi);
      if (patches.size() == before) throw InputError(o.where + ": polygon has zero area (zero-size primitive)");
      checkPlacement(patches, first, o);
      continue;
    }
    if (o.type == PrimitiveType::Quad) {
      Polygon p{{o.quad[0], o.quad[1], o.quad[2], o.quad[3]}, 4};
      for (int i = 0; i < 4; ++i) p.v[i] = Vec3(xf * glm::dvec4(p.v[i], 1.0));
      double r = p.radius();
      // A quad whose vertices are not in convex counter-clockwise order is a user error, not a mesh.
      Vec3 nrm = p.areaVector();
      if (glm::length(nrm) <= 1e-12 * r * r)
        throw InputError(o.where + ".vertices: quad has zero area (zero-size primitive)");
      for (int i = 0; i < 4; ++i) {
        Vec3 e0 = p.v[(i + 1) % 4] - p.v[i], e1 = p.v[(i + 2) % 4] - p.v[(i + 1) % 4];
        if (glm::dot(glm::cross(e0, e1), nrm) < -1e-9 * r * r)
          throw InputError(o.where + ".vertices: quad is not convex with consistent winding");
      }
      sink.add(p, mat, oi);
      checkPlacement(patches, first, o);
      continue;
    }
    MeshBuilder b;
    Object round = o;  // radii scaled so that the polygons keep the surface's area
    const double k = areaPreservingScale(o, seg);
    round.radius *= k;
    round.radius2 *= k;
    switch (o.type) {
      case PrimitiveType::Box: buildBox(b, o); break;
      case PrimitiveType::Disk: buildDisk(b, round, seg); break;
      case PrimitiveType::Sphere: buildSphere(b, round, seg); break;
      case PrimitiveType::Cylinder: buildFrustum(b, round, round.radius, round.radius, seg); break;
      case PrimitiveType::Cone: buildFrustum(b, round, round.radius, round.radius2, seg); break;
      case PrimitiveType::Ring: buildRing(b, round, seg); break;
      default: break;
    }
    std::size_t before = patches.size();
    emitMesh(b.mesh(), xf, mirrored, sink, mat, oi);
    if (patches.size() == before)
      throw InputError(o.where + ": every face is degenerate after the transform (zero-size primitive)");
    checkPlacement(patches, first, o);
  }
  const std::string file = scene.path.empty() ? std::string("<scene>") : scene.path;
  bool emits = false;
  Rgb power(0.0);
  for (const Patch& p : patches) {
    emits = emits || scene.materials[p.material].emitter();
    power += kPi * scene.materials[p.material].emission * p.area;
  }
  if (!emits) throw InputError(file + ": the scene has no emitting surface (give a material an \"emission\")");
  if (!(maxComponent(power) <= limits::kMaxPowerW))
    throw InputError(file + ": the emitters' total power exceeds " + std::to_string(limits::kMaxPowerW) + " W");
  return patches;
}

}  // namespace hr
