// A solved scene as a self-contained snapshot: patches, the element quadtrees with their radiosity,
// cameras and materials. Everything downstream (images, .vtp, the .ghrs file, later the viewer)
// reads this, so a saved solution renders exactly like a fresh one.
#pragma once
#include <hr/curved_surface.h>
#include <hr/geometry.h>
#include <hr/section_file.h>

#include <array>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace hr {

struct SolutionElement {
  Polygon poly;
  std::uint32_t patch = 0;
  std::uint32_t firstChild = kNone;
  std::uint32_t level = 0;
  Rgb radiosity{0.0};  // W/m^2
  bool leaf() const { return firstChild == kNone; }
};

/// An extension's part of a solution: its name in the extension table, the version of its format and
/// the bytes its save() wrote (the solution file's tagged extension section).
struct ExtensionData {
  std::string name;  // empty: the run had no extension
  std::uint32_t version = 0;
  std::string bytes;  // as loaded, or to be saved when `write` is empty
  /// Saving a fresh run: writes the bytes straight into the file, run more than once (sized and
  /// checksummed first), so that they are never held whole (a glossy solve's run to gigabytes).
  std::function<void(std::ostream&)> write;
};

struct Solution {
  std::string sceneName;
  std::string host = "bright";
  std::string algorithm = "diffuse";
  std::vector<Patch> patches;            // element i < patches.size() is the root of patch i
  std::vector<SolutionElement> elements;
  std::vector<Material> materials;
  std::vector<Camera> cameras;
  std::uint32_t objectCount = 0;

  ExtensionData extension;
  /// Opaque sections saved and loaded verbatim besides the core's, each with its own checksum (an
  /// extension's state: its name, its format version and its bytes, as it chooses). See setSection().
  std::vector<Section> sections;

  /// Per leaf corner, smoothed radiosity (W/m^2): filled by reconstruct().
  std::vector<std::array<Rgb, 4>> cornerRadiosity;
  /// Per object, its curved surface (hr/curved_surface.h), or empty when the solution holds none:
  /// the display shades leaves of curved objects at their surface's exact normal (the "surfaces"
  /// section, read by reconstruct()); elsewhere it estimates a vertex's normal from the polygons
  /// meeting there.
  std::vector<CurvedSurface> surfaces;
};

/// Adds (or replaces) an opaque section of the .ghrs file; the core's own names are reserved.
void setSection(Solution& s, const std::string& name, std::string bytes);
/// The payload of an opaque section, or nullptr.
const std::string* findSection(const Solution& s, const std::string& name);

/// Smooth reconstruction without bias (reconstruct.cpp): each leaf corner takes the area-weighted mean
/// radiosity of the leaves of the same object and material that share that point and face within 30
/// degrees of it (creases, objects, materials and emitters stay sharp), hidden leaves (a surface
/// just in front, or a coplanar cover) left out of visible leaves' corners; then kMeanPasses move
/// the corners, within their leaves' range, toward drawing each leaf's own mean. A solution with a
/// "display" section reading "flat" keeps each element's own value instead; one holding a host's
/// own corners (encodeDisplayCorners) takes those.
void reconstruct(Solution& s);

/// Passes that move smoothed corners toward drawing each leaf's own mean (reconstruct; the VISION-like
/// host's smoothing too): on the Cornell box at eps 2e-4 the image's rel. RMSE against the path tracer
/// went 0.053 -> 0.043 / 0.041 with 1 / 2 passes, 0.041 with 4.
inline constexpr int kMeanPasses = 2;

/// Per element, 1 if it is a leaf hidden by a surface just in front of it or by a coplanar cover
/// (the leaves whose radiosity smoothing must not spread onto visible neighbours), else 0.
std::vector<char> hiddenLeaves(const Solution& s);

/// A host that smooths in its own terms (the VISION-like host, across its parameter space) hands its
/// per-element corner radiosity (W/m^2, in polygon vertex order) to every output and to the .ghrs
/// file as the "display" section: kDisplayCorners, then 12 doubles per element.
inline constexpr const char* kDisplayCorners = "corners";
std::string encodeDisplayCorners(const std::vector<std::array<Rgb, 4>>& corners);
/// Throws InputError naming the section when its size does not match the elements or a value is
/// negative or not finite.
std::vector<std::array<Rgb, 4>> decodeDisplayCorners(const Solution& s, const std::string& payload);

/// The exact shading normal at x on patch p: its object's curved surface's (s.surfaces), turned to
/// the patch's side, or Vec3(0) where the object is flat, unknown or the normal undefined there.
Vec3 surfaceNormal(const Solution& s, std::uint32_t patch, const Vec3& x);

/// Finds the leaf of patch p that holds point x (descends the quadtree by point location).
std::uint32_t locateLeaf(const Solution& s, std::uint32_t patch, const Vec3& x);
/// Smoothly reconstructed radiosity at point x on the leaf, W/m^2.
Rgb interpolate(const Solution& s, std::uint32_t leaf, const Vec3& x);
/// Any per-corner values of a leaf (e.g. radiance toward an eye) interpolated at x the same way.
Rgb interpolateCorners(const Solution& s, std::uint32_t leaf, const Vec3& x, const std::array<Rgb, 4>& corners);
/// The weights interpolateCorners gives a leaf's four corners at x (they sum to 1; a triangle's fourth is 0).
std::array<double, 4> cornerWeights(const Solution& s, std::uint32_t leaf, const Vec3& x);

/// Versioned binary solution file (.ghrs, format 2: tagged sections with a CRC-32 each, see
/// solution_io.cpp). Throws InputError naming the section on a damaged, truncated or foreign file.
void saveSolution(const Solution& s, const std::string& path);
Solution loadSolution(const std::string& path);
std::string serializeSolution(const Solution& s);
/// verifyChecksums = false: the fuzzer's way past the CRCs to the validation behind them.
Solution parseSolution(std::string_view bytes, const std::string& path, bool verifyChecksums = true);

}  // namespace hr
