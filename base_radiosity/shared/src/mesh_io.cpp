// Mesh files: OBJ with MTL through tinyobjloader (fed from memory: the OBJ and every material library
// are read through readInputFile, so no library opens a path of the file's choosing), PLY through our
// own reader (ply_reader.cpp). OBJ materials map onto modified Phong (Kd -> diffuse, Ks -> specular,
// Ns -> exponent, Ke -> emitted radiance) and are validated against the limits table like scene
// materials. Faces with more than four vertices are fanned into triangles.
#include <hr/echo.h>
#include <hr/geometry.h>
#include <hr/input_file.h>
#include <hr/limits.h>
#include <tiny_obj_loader.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "ply_reader.h"

namespace hr {

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

namespace {

Rgb mtlColour(const std::string& file, const std::string& mat, const char* key, const float* c, const limits::Range& r) {
  Rgb v(c[0], c[1], c[2]);
  for (int i = 0; i < 3; ++i)
    if (!limits::within(v[i], r))
      throw InputError(file + ": material " + echo(mat) + ": " + key + " must be finite and in " + r.text());
  return v;
}

/// Splits text into lines, with line numbers from 1 (any of \n, \r\n).
template <class F>
void forLines(const std::string& text, F&& f) {
  std::istringstream in(text);
  std::string line;
  for (std::size_t no = 1; std::getline(in, line); ++no) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    f(no, line);
  }
}

/// tinyobjloader reads "nan" and "inf" as numbers without complaint, and a face of a million
/// vertices as one: find both first, by line.
void precheckObj(const std::string& text, const std::string& path) {
  forLines(text, [&](std::size_t no, const std::string& line) {
    std::size_t b = line.find_first_not_of(" \t");
    if (b == std::string::npos) return;
    if (line.compare(b, 2, "v ") == 0 || line.compare(b, 2, "v\t") == 0) {
      std::string low = line;
      for (auto& c : low) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (low.find("nan") != std::string::npos || low.find("inf") != std::string::npos)
        throw InputError(path + ": line " + std::to_string(no) + ": vertex has a non-finite coordinate");
    }
    if (line.compare(b, 2, "f ") == 0 || line.compare(b, 2, "f\t") == 0) {
      std::istringstream ls(line.substr(b + 2));
      std::size_t n = 0;
      for (std::string t; ls >> t;) ++n;
      if (n > limits::kMaxFaceVertices)
        throw InputError(path + ": line " + std::to_string(no) + ": face with " + std::to_string(n) +
                         " vertices, more than the limit of " + std::to_string(limits::kMaxFaceVertices));
    }
  });
}

/// The text of every "mtllib" the OBJ names (relative to its folder), read through readInputFile.
std::string materialLibraries(const std::string& text, const std::string& path) {
  std::string all;
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  forLines(text, [&](std::size_t no, const std::string& line) {
    std::istringstream ls(line);
    std::string key;
    if (!(ls >> key) || key != "mtllib") return;
    for (std::string name; ls >> name;) {
      try {
        std::string mtl = readInputFile((dir / name).string(), "material library", limits::kMaxMeshBytes);
        stripUtf8Bom(mtl);
        all += mtl + "\n";
      } catch (const InputError& e) {
        throw InputError(path + ": line " + std::to_string(no) + ": mtllib: " + e.what());
      }
    }
  });
  return all;
}

MeshData parseObj(std::string text, const std::string& path, bool readLibraries) {
  stripUtf8Bom(text);
  precheckObj(text, path);
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = false;
  tinyobj::ObjReader rd;
  if (!rd.ParseFromString(text, readLibraries ? materialLibraries(text, path) : std::string(), cfg))
    throw InputError(path + ": cannot read OBJ: " + clipMessage(rd.Error(), 300));
  const auto& at = rd.GetAttrib();
  MeshData md;
  for (const auto& m : rd.GetMaterials()) {
    Material mat;
    mat.name = m.name;
    mat.diffuse = mtlColour(path, m.name, "Kd", m.diffuse, limits::kReflectance);
    mat.specular = mtlColour(path, m.name, "Ks", m.specular, limits::kReflectance);
    mat.emission = mtlColour(path, m.name, "Ke", m.emission, limits::kEmission);
    if (!limits::within(m.shininess, limits::kExponent))
      throw InputError(path + ": material " + echo(m.name) + ": Ns must be finite and in " + limits::kExponent.text());
    mat.exponent = m.shininess;
    for (int c = 0; c < 3; ++c)
      if (mat.diffuse[c] + mat.specular[c] > 1.0)
        throw InputError(path + ": material " + echo(m.name) + ": Kd + Ks > 1 (would create energy)");
    md.materials.push_back(mat);
  }
  const std::size_t nv = at.vertices.size() / 3;
  for (std::size_t i = 0; i < at.vertices.size(); ++i)
    if (!limits::within(at.vertices[i], limits::kCoordinate))
      throw InputError(path + ": vertex " + std::to_string(i / 3 + 1) + " has a coordinate (" +
                       std::to_string(at.vertices[i]) + ") that is not finite or outside " + limits::kCoordinate.text());
  for (const auto& sh : rd.GetShapes()) {
    std::size_t off = 0;
    for (std::size_t f = 0; f < sh.mesh.num_face_vertices.size(); ++f) {
      int k = sh.mesh.num_face_vertices[f];
      std::vector<Vec3> pts;
      for (int j = 0; j < k; ++j) {
        if (off + std::size_t(j) >= sh.mesh.indices.size())
          throw InputError(path + ": shape " + echo(sh.name) + " face " + std::to_string(f + 1) + ": malformed face");
        int idx = sh.mesh.indices[off + j].vertex_index;
        if (idx < 0 || static_cast<std::size_t>(idx) >= nv)
          throw InputError(path + ": shape " + echo(sh.name) + " face " + std::to_string(f + 1) +
                           ": vertex index out of range");
        pts.push_back({at.vertices[3 * idx], at.vertices[3 * idx + 1], at.vertices[3 * idx + 2]});
      }
      int slot = f < sh.mesh.material_ids.size() ? sh.mesh.material_ids[f] : -1;
      if (slot >= static_cast<int>(md.materials.size())) slot = -1;
      pushPolygon(md, pts, slot);
      off += std::size_t(k);
    }
  }
  if (md.faces.empty()) throw InputError(path + ": OBJ file has no faces");
  return md;
}

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

MeshData parseMesh(const std::string& bytes, const std::string& path, bool readMaterialLibraries) {
  std::string ext = lowerExtension(path);
  if (ext == ".obj") return parseObj(bytes, path, readMaterialLibraries);
  if (ext == ".ply") return parsePly(bytes, path);
  throw InputError(path + ": unsupported mesh format " + echo(ext) + " (valid: .obj, .ply)");
}

MeshData readMeshFile(const std::string& path) {
  std::string ext = lowerExtension(path);
  if (ext != ".obj" && ext != ".ply") throw InputError(path + ": unsupported mesh format " + echo(ext) + " (valid: .obj, .ply)");
  return parseMesh(readInputFile(path, "mesh file", limits::kMaxMeshBytes), path, true);
}

}  // namespace hr
