// Mesh files: OBJ with MTL through tinyobjloader, PLY through OpenMesh's reader. OBJ materials map
// onto modified Phong (Kd -> diffuse, Ks -> specular, Ns -> exponent, Ke -> emitted radiance) and
// are validated like scene materials. Faces with more than four vertices are fanned into triangles.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <hr/geometry.h>
#include <tiny_obj_loader.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace hr {
namespace {

void pushPolygon(MeshData& md, const std::vector<Vec3>& pts, int slot) {
  if (pts.size() < 3) return;
  if (pts.size() <= 4) {
    MeshFace f;
    f.poly.n = static_cast<int>(pts.size());
    for (int i = 0; i < f.poly.n; ++i) f.poly.v[i] = pts[i];
    f.materialSlot = slot;
    md.faces.push_back(f);
    return;
  }
  for (std::size_t i = 1; i + 1 < pts.size(); ++i) {
    MeshFace f;
    f.poly = {{pts[0], pts[i], pts[i + 1], Vec3(0.0)}, 3};
    f.materialSlot = slot;
    md.faces.push_back(f);
  }
}

Rgb mtlColour(const std::string& file, const std::string& mat, const char* key, const float* c) {
  Rgb v(c[0], c[1], c[2]);
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(v[i]) || v[i] < 0.0)
      throw InputError(file + ": material \"" + mat + "\": " + key + " must be finite and >= 0");
  return v;
}

/// tinyobjloader reads "nan" and "inf" as numbers without complaint; find them first, by line.
void rejectNonFiniteVertices(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  for (std::size_t no = 1; std::getline(in, line); ++no) {
    if (line.rfind("v ", 0) != 0) continue;
    std::string low = line;
    for (auto& c : low) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (low.find("nan") != std::string::npos || low.find("inf") != std::string::npos)
      throw InputError(path + ": line " + std::to_string(no) + ": vertex has a non-finite coordinate");
  }
}

MeshData readObj(const std::string& path) {
  rejectNonFiniteVertices(path);
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = false;
  cfg.mtl_search_path = std::filesystem::path(path).parent_path().string();
  tinyobj::ObjReader rd;
  if (!rd.ParseFromFile(path, cfg)) throw InputError(path + ": cannot read OBJ: " + rd.Error());
  const auto& at = rd.GetAttrib();
  MeshData md;
  for (const auto& m : rd.GetMaterials()) {
    Material mat;
    mat.name = m.name;
    mat.diffuse = mtlColour(path, m.name, "Kd", m.diffuse);
    mat.specular = mtlColour(path, m.name, "Ks", m.specular);
    mat.emission = mtlColour(path, m.name, "Ke", m.emission);
    if (!std::isfinite(m.shininess) || m.shininess < 0.0f)
      throw InputError(path + ": material \"" + m.name + "\": Ns must be finite and >= 0");
    mat.exponent = m.shininess;
    for (int c = 0; c < 3; ++c)
      if (mat.diffuse[c] + mat.specular[c] > 1.0)
        throw InputError(path + ": material \"" + m.name + "\": Kd + Ks > 1 (would create energy)");
    md.materials.push_back(mat);
  }
  const std::size_t nv = at.vertices.size() / 3;
  for (std::size_t i = 0; i < at.vertices.size(); ++i)
    if (!std::isfinite(at.vertices[i]))
      throw InputError(path + ": vertex " + std::to_string(i / 3 + 1) + " has a non-finite coordinate");
  for (const auto& sh : rd.GetShapes()) {
    std::size_t off = 0;
    for (std::size_t f = 0; f < sh.mesh.num_face_vertices.size(); ++f) {
      int k = sh.mesh.num_face_vertices[f];
      std::vector<Vec3> pts;
      for (int j = 0; j < k; ++j) {
        int idx = sh.mesh.indices[off + j].vertex_index;
        if (idx < 0 || static_cast<std::size_t>(idx) >= nv)
          throw InputError(path + ": shape \"" + sh.name + "\" face " + std::to_string(f + 1) +
                           ": vertex index out of range");
        pts.push_back({at.vertices[3 * idx], at.vertices[3 * idx + 1], at.vertices[3 * idx + 2]});
      }
      int slot = f < sh.mesh.material_ids.size() ? sh.mesh.material_ids[f] : -1;
      if (slot >= static_cast<int>(md.materials.size())) slot = -1;
      pushPolygon(md, pts, slot);
      off += k;
    }
  }
  if (md.faces.empty()) throw InputError(path + ": OBJ file has no faces");
  return md;
}

MeshData readPly(const std::string& path) {
  struct Traits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
  };
  OpenMesh::PolyMesh_ArrayKernelT<Traits> mesh;
  OpenMesh::IO::Options opt;
  if (!OpenMesh::IO::read_mesh(mesh, path, opt)) throw InputError(path + ": cannot read PLY file (malformed or unreadable)");
  MeshData md;
  for (auto vh : mesh.vertices()) {
    auto p = mesh.point(vh);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw InputError(path + ": vertex " + std::to_string(vh.idx()) + " has a non-finite coordinate");
  }
  for (auto fh : mesh.faces()) {
    std::vector<Vec3> pts;
    for (auto vh : mesh.fv_range(fh)) {
      auto p = mesh.point(vh);
      pts.push_back({p[0], p[1], p[2]});
    }
    pushPolygon(md, pts, -1);
  }
  if (md.faces.empty()) throw InputError(path + ": PLY file has no faces");
  return md;
}

}  // namespace

MeshData readMeshFile(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path + ": mesh file does not exist");
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".obj") return readObj(path);
  if (ext == ".ply") return readPly(path);
  throw InputError(path + ": unsupported mesh format \"" + ext + "\" (valid: .obj, .ply)");
}

}  // namespace hr
