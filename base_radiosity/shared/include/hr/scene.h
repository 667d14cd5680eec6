// The scene as the user described it, before any tessellation: materials, objects with their
// primitive parameters, cameras and solver settings. Loaded from JSON by loadScene(); every value is
// validated there, so the rest of the core may assume a physically valid scene.
#pragma once
#include <hr/types.h>

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace hr {

/// Modified Phong: f = rho_d/pi + rho_s (n+2)/(2 pi) cos^n(alpha). Emission is the radiance of a
/// Lambertian emitter, W/(m^2 sr).
struct Material {
  std::string name;
  Rgb diffuse{0.0};
  Rgb specular{0.0};
  double exponent = 1.0;
  Rgb emission{0.0};
  bool glossy() const { return maxComponent(specular) > 0.0; }
  bool emitter() const { return maxComponent(emission) > 0.0; }
};

struct Transform {
  Vec3 translate{0.0};
  Vec3 rotateDeg{0.0};  // applied X, then Y, then Z
  Vec3 scale{1.0};
  std::optional<glm::dmat4> explicitMatrix;  // MGF transforms compose arbitrarily; used when set
  glm::dmat4 matrix() const;
};

/// Curved primitives stay whole here (a host that does not tessellate can keep them); the
/// BRIGHT-like host tessellates them at load (settings.tessellation segments around).
enum class PrimitiveType { Quad, Box, Disk, Sphere, Cylinder, Cone, Ring, Polygon, Mesh };
const char* primitiveName(PrimitiveType t);

struct Object {
  PrimitiveType type = PrimitiveType::Quad;
  std::string where;  // "file:objects[3]" for messages
  std::string material;  // empty for OBJ meshes that carry their own
  std::array<Vec3, 4> quad{};
  Vec3 min{0.0}, max{0.0};
  bool inward = false;
  Vec3 center{0.0}, normal{0.0, 0.0, 1.0}, axis{0.0, 0.0, 1.0}, base{0.0};
  double radius = 0.0, height = 0.0;
  double radius2 = 0.0;       // cone: radius at base + height * axis; ring: outer radius
  std::vector<Vec3> points;   // polygon: any simple planar polygon, MGF seams for holes allowed
  std::string group;          // MGF object context ("o" names, joined by "/"), for reports
  std::string file;  // mesh file, resolved against the scene's folder
  Transform transform;
};

struct Camera {
  std::string name;
  Vec3 eye{0.0, 0.0, 5.0}, lookAt{0.0}, up{0.0, 1.0, 0.0};
  double fovYDeg = 45.0;
  int width = 320, height = 240;
};

/// Solver defaults a scene may set; command-line flags override them.
struct Settings {
  double eps = 2e-4;           // relative refinement threshold (see docs/solver.md)
  int maxLevel = 6;            // quadtree depth below a root patch
  double minArea = 0.0;        // m^2; 0 means: scene area * 1e-6
  int raysPerLink = 4;         // shadow rays per link
  int maxIterations = 200;
  double tolerance = 1e-4;     // stop when the power change is below this fraction of emitted power
  int tessellation = 16;       // segments around curved primitives
  std::uint64_t seed = 1;
};

struct Scene {
  std::string path;  // file it came from ("" for built-in)
  std::string name;
  std::vector<Material> materials;
  std::map<std::string, std::uint32_t> materialIndex;
  std::vector<Object> objects;
  std::vector<Camera> cameras;
  Settings settings;
  std::vector<std::string> warnings;  // unknown keys etc.; printed by the caller
  std::vector<std::string> dropped;   // what an importer dropped or approximated, one line each
  std::map<std::string, std::size_t> entityCounts;  // importer's source entities ("mgf cone": 461)
};

/// Parses and validates a JSON scene. Throws InputError naming the file and key on any problem.
Scene loadScene(const std::string& path);
Scene parseScene(const std::string& jsonText, const std::string& path);
/// Objects (indices in file order, as images' object ids) whose material emits: image comparisons
/// leave them out, since their pixels measure the pixel filter on a bright edge, not the light.
std::vector<std::uint32_t> emitterObjects(const Scene& scene);
/// The built-in default scene (a Cornell-box-like room), used when no file is given.
Scene defaultScene();
extern const char* kDefaultSceneJson;

}  // namespace hr
