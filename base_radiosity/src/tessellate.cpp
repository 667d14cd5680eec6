// Turns scene objects into root patches. Primitives are built as OpenMesh polygon meshes (shared
// vertices, consistent orientation), then each face becomes one planar patch. Non-planar quads are
// split into two triangles; zero-area faces are dropped and counted, never silently.
#include <hr/geometry.h>

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <glm/gtc/matrix_transform.hpp>

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

/// Orthonormal frame around a unit axis.
void frame(const Vec3& w, Vec3& u, Vec3& v) {
  Vec3 a = std::abs(w.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  u = glm::normalize(glm::cross(a, w));
  v = glm::cross(w, u);
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
    b.face({top, rings[0][i], rings[0][j]});
    for (int s = 0; s + 1 < stacks - 1; ++s) b.face({rings[s][i], rings[s + 1][i], rings[s + 1][j], rings[s][j]});
    b.face({bottom, rings[stacks - 2][j], rings[stacks - 2][i]});
  }
}

void buildCylinder(MeshBuilder& b, const Object& o, int seg) {
  Vec3 w = glm::normalize(o.axis), u, v;
  frame(w, u, v);
  std::vector<PolyMesh::VertexHandle> lo, hi;
  for (int i = 0; i < seg; ++i) {
    double t = 2.0 * kPi * i / seg;
    Vec3 r = o.radius * (std::cos(t) * u + std::sin(t) * v);
    lo.push_back(b.vertex(o.base + r));
    hi.push_back(b.vertex(o.base + r + o.height * w));
  }
  for (int i = 0; i < seg; ++i) {
    int j = (i + 1) % seg;
    b.face({lo[i], lo[j], hi[j], hi[i]});  // outward-facing open tube
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

void emitMesh(const PolyMesh& m, const glm::dmat4& xf, PatchSink& sink, std::uint32_t mat, std::uint32_t obj) {
  for (auto fh : m.faces()) {
    std::vector<Vec3> pts;
    for (auto vh : m.fv_range(fh)) pts.push_back(Vec3(xf * glm::dvec4(toVec(m.point(vh)), 1.0)));
    if (pts.size() == 3 || pts.size() == 4) {
      Polygon p;
      p.n = static_cast<int>(pts.size());
      for (int i = 0; i < p.n; ++i) p.v[i] = pts[i];
      sink.add(p, mat, obj);
    }
  }
}

}  // namespace

std::vector<Patch> buildPatches(Scene& scene, TessellationReport& report) {
  std::vector<Patch> patches;
  PatchSink sink(patches, report, 1e-6);
  const int seg = scene.settings.tessellation;
  for (std::uint32_t oi = 0; oi < scene.objects.size(); ++oi) {
    const Object& o = scene.objects[oi];
    glm::dmat4 xf = o.transform.matrix();
    std::uint32_t mat = o.material.empty() ? kNone : scene.materialIndex.at(o.material);
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
      continue;
    }
    MeshBuilder b;
    switch (o.type) {
      case PrimitiveType::Box: buildBox(b, o); break;
      case PrimitiveType::Disk: buildDisk(b, o, seg); break;
      case PrimitiveType::Sphere: buildSphere(b, o, seg); break;
      case PrimitiveType::Cylinder: buildCylinder(b, o, seg); break;
      default: break;
    }
    std::size_t before = patches.size();
    emitMesh(b.mesh(), xf, sink, mat, oi);
    if (patches.size() == before)
      throw InputError(o.where + ": every face is degenerate after the transform (zero-size primitive)");
  }
  bool emits = false;
  for (const Patch& p : patches) emits = emits || scene.materials[p.material].emitter();
  if (!emits)
    throw InputError((scene.path.empty() ? std::string("<scene>") : scene.path) +
                     ": the scene has no emitting surface (give a material an \"emission\")");
  return patches;
}

}  // namespace hr
