// The PLY reader (ASCII and binary, either byte order): vertices with x, y, z and faces with a
// vertex_indices (or vertex_index) list; other elements and properties are read and skipped. Written
// for hostile files: the header must end within 64 KiB, every declared count is checked against the
// bytes that follow before anything is allocated, faces are bounded by limits::kMaxFaceVertices.
// Private to hr_core (OpenMesh's reader loops forever on a header without end_header and allocates
// whatever a header declares).
#pragma once
#include <hr/geometry.h>

#include <string>

namespace hr {

/// Appends a polygon read from a mesh file: triangles and quads as they are, larger polygons fanned
/// (mesh_io.cpp). slot: the file's material index, -1 for none.
void pushPolygon(MeshData& md, const std::vector<Vec3>& pts, int slot);

/// Throws InputError naming path and the header line or element.
MeshData parsePly(const std::string& bytes, const std::string& path);

}  // namespace hr
