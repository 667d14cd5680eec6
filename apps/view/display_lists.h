// The viewer's two lists (paper §5.2): the leaves of diffuse surfaces, whose per-vertex colours are
// fixed after the solve and uploaded once, and the leaves an extension simulates, whose per-vertex
// colours follow the eye. Both are drawn exactly as hr::render shades a pixel: a triangle leaf
// interpolates its three corners; a quad is four triangles around its centre, whose value is the
// mean of the corners (solution.cpp interpolateCorners), so that GPU interpolation of the
// per-vertex radiance reproduces the still images. Vertices carry linear radiance, W/(m^2 sr); the
// tone mapping happens per pixel (tone_shader.h). Free of VTK.
#pragma once
#include <hr/extension_display.h>
#include <hr/solution.h>

#include <cstdint>
#include <vector>

namespace view {

struct DisplayList {
  std::vector<float> points;              // x, y, z per vertex, m
  std::vector<float> diffuse;             // r, g, b per vertex: the host's smooth B / pi, W/(m^2 sr)
  std::vector<std::uint32_t> triangles;   // 3 vertex indices each, counter-clockwise seen from the front
  std::vector<std::uint32_t> triangleLeaf;  // per triangle: its leaf (element id), for picking
  /// Glossy list only: per vertex, 4 corner indices into ExtensionDisplay::cornerValues(): a leaf
  /// corner names itself then hr::kNone; a quad's centre names its four corners (their mean); a
  /// point on an edge (a finer neighbour's corner, see buildDisplayLists) names the edge's two
  /// corners then hr::kNone twice, weighted by edgeT.
  std::vector<std::uint32_t> corners;
  std::vector<float> edgeT;  // glossy list only, per vertex: the second corner's weight on an edge point
  std::size_t vertexCount() const { return points.size() / 3; }
};

struct DisplayLists {
  DisplayList diffuse, glossy;
};

/// Splits the solution's leaves: into `glossy` those `display` simulates (none without one). A
/// leaf whose edge holds corners of finer neighbours (T-junctions) gets them as vertices of its own,
/// at the value its interpolation has there: the same image, and no pinholes where the neighbours'
/// triangles meet its edge (through which the background darkened single pixels).
DisplayLists buildDisplayLists(const hr::Solution& s, const hr::ExtensionDisplay* display);

/// The glossy list's per-vertex extension radiance after display.update(), W/(m^2 sr), into out
/// (3 floats per vertex).
void glossyRadiance(const DisplayList& glossy, const hr::ExtensionDisplay& display, float* out);

}  // namespace view
