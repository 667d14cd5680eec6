// Root patches: every scene object tessellated into planar triangles and quads at load (the
// BRIGHT-like host). Curved primitives are tessellated with a configurable number of segments.
#pragma once
#include <hr/polygon.h>
#include <hr/scene.h>

#include <string>
#include <vector>

namespace hr {

struct Patch {
  Polygon poly;
  Vec3 normal{0.0, 0.0, 1.0};
  double area = 0.0;
  std::uint32_t material = 0;
  std::uint32_t object = 0;  // index of the scene object, in file order
};

struct TessellationReport {
  std::size_t droppedZeroArea = 0;
  std::size_t splitNonPlanar = 0;
};

/// Tessellates every object (mesh files are read here, and their materials appended to
/// scene.materials). Throws InputError for unreadable or malformed meshes and for scenes with no
/// emitting surface. Zero-area faces are dropped and counted.
std::vector<Patch> buildPatches(Scene& scene, TessellationReport& report);

/// Ear clipping in the polygon's plane (Newell normal): handles non-convex polygons and MGF's holes
/// given as seams (an edge walked in both directions). Quads that are convex stay whole. Shared by
/// both hosts (the VISION-like one splits only the polygons it cannot keep whole).
std::vector<Polygon> triangulate(std::vector<Vec3> pts);

/// Area of n planar trapezoids joining two coaxial circles (radius r0 at height z0, r1 at z1) with
/// vertices at the same n angles: one band of a tessellated surface of revolution. What the
/// tessellation's area-keeping radius factors are computed from (spheres; the MGF torus).
double polygonBandArea(double r0, double z0, double r1, double z1, int n);

/// Reads OBJ (with MTL, via tinyobjloader) or PLY (via OpenMesh) into polygons; exposed for tests.
struct MeshFace {
  Polygon poly;
  int materialSlot = -1;  // index into the file's own materials, -1 for none
};
struct MeshData {
  std::vector<MeshFace> faces;
  std::vector<Material> materials;  // OBJ materials mapped onto the modified Phong model
};
MeshData readMeshFile(const std::string& path);
/// The same from bytes already in memory (the format from path's extension); OBJ material libraries
/// are read relative to path unless readMaterialLibraries is false (the fuzzers).
MeshData parseMesh(const std::string& bytes, const std::string& path, bool readMaterialLibraries = true);

}  // namespace hr
