// JSON scene reader. Validation lives here so that every later stage can trust the scene: each
// error names the file and the JSON path of the offending key; unknown keys become warnings.
#include <hr/echo.h>
#include <hr/input_file.h>
#include <hr/limits.h>
#include <hr/mgf.h>
#include <hr/scene.h>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <hr/json_strict.h>

namespace hr {
namespace {

using json = nlohmann::json;

class Reader {
 public:
  Reader(std::string file, Scene& scene) : file_(std::move(file)), scene_(scene) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw InputError(file_ + ": " + key + ": " + what);
  }

  void checkKeys(const json& obj, const std::string& key, std::initializer_list<const char*> known) {
    std::set<std::string> k(known.begin(), known.end());
    for (auto it = obj.begin(); it != obj.end(); ++it)
      if (!k.count(it.key()))
        scene_.warnings.push_back(file_ + ": " + key + ": unknown key " + echo(it.key()) + " ignored");
  }

  const json& member(const json& obj, const std::string& key, const char* name) const {
    if (!obj.contains(name)) fail(key, std::string("missing required key \"") + name + "\"");
    return obj.at(name);
  }

  double number(const json& v, const std::string& key) const {
    if (!v.is_number()) fail(key, "expected a number, got " + std::string(v.type_name()));
    double d = v.get<double>();
    if (!std::isfinite(d)) fail(key, "value is not finite");
    return d;
  }

  /// A number inside a range of the limits table (README "Limits").
  double bounded(const json& v, const std::string& key, const limits::Range& r) const {
    double d = number(v, key);
    if (!r.contains(d)) fail(key, "value " + fmt(d) + " outside the allowed range " + r.text());
    return d;
  }

  /// Three numbers, each inside r (coordinates by default: every point a ray must reach).
  Vec3 vec3(const json& v, const std::string& key, const limits::Range& r = limits::kCoordinate) const {
    if (!v.is_array() || v.size() != 3) fail(key, "expected an array of 3 numbers");
    return {bounded(v[0], key + "[0]", r), bounded(v[1], key + "[1]", r), bounded(v[2], key + "[2]", r)};
  }

  Rgb colour(const json& obj, const std::string& key, const char* name, const limits::Range& r) const {
    if (!obj.contains(name)) return Rgb(0.0);
    Rgb c = vec3(obj.at(name), key + "." + name, r);
    return c;
  }

  std::string string(const json& v, const std::string& key) const {
    if (!v.is_string()) fail(key, "expected a string");
    return v.get<std::string>();
  }

  int integer(const json& v, const std::string& key, const limits::Range& r) const {
    double d = number(v, key);
    if (d != std::floor(d) || !r.contains(d)) fail(key, "expected an integer in " + r.text() + ", got " + fmt(d));
    return static_cast<int>(d);
  }

  static std::string fmt(double d) {
    std::ostringstream s;
    s << d;
    return s.str();
  }

  const std::string& file() const { return file_; }

 private:
  std::string file_;
  Scene& scene_;
};

void readMaterials(Reader& r, const json& mats, Scene& s) {
  if (!mats.is_object()) r.fail("materials", "expected an object of name -> material");
  for (auto it = mats.begin(); it != mats.end(); ++it) {
    const std::string key = "materials." + it.key().substr(0, limits::kMaxEcho);
    // An empty name could never be referenced (an object's empty "material" means "none").
    if (it.key().empty()) r.fail("materials", "a material name must not be empty");
    const json& m = it.value();
    if (!m.is_object()) r.fail(key, "expected an object");
    r.checkKeys(m, key, {"diffuse", "specular", "exponent", "emission"});
    Material mat;
    mat.name = it.key();
    mat.diffuse = r.colour(m, key, "diffuse", limits::kReflectance);
    mat.specular = r.colour(m, key, "specular", limits::kReflectance);
    mat.emission = r.colour(m, key, "emission", limits::kEmission);
    if (m.contains("exponent")) mat.exponent = r.bounded(m.at("exponent"), key + ".exponent", limits::kExponent);
    for (int c = 0; c < 3; ++c)
      if (mat.diffuse[c] + mat.specular[c] > 1.0)
        r.fail(key, "diffuse + specular = " + std::to_string(mat.diffuse[c] + mat.specular[c]) +
                        " > 1 in channel " + std::to_string(c) + " (the material would create energy)");
    s.materialIndex[mat.name] = static_cast<std::uint32_t>(s.materials.size());
    s.materials.push_back(mat);
  }
}

Transform readTransform(Reader& r, const json& t, const std::string& key) {
  if (!t.is_object()) r.fail(key, "expected an object");
  r.checkKeys(t, key, {"translate", "rotate_deg", "scale"});
  Transform x;
  if (t.contains("translate")) x.translate = r.vec3(t["translate"], key + ".translate");
  if (t.contains("rotate_deg")) x.rotateDeg = r.vec3(t["rotate_deg"], key + ".rotate_deg", limits::kAngleDeg);
  if (t.contains("scale")) {
    const json& sc = t["scale"];
    x.scale = sc.is_number() ? Vec3(r.bounded(sc, key + ".scale", limits::kScale)) : r.vec3(sc, key + ".scale", limits::kScale);
    for (int i = 0; i < 3; ++i)
      if (x.scale[i] == 0.0) r.fail(key + ".scale", "zero scale makes every face degenerate");
  }
  return x;
}

/// A size: > 0 (else a zero-size primitive) and within the limits table.
double size(Reader& r, const json& v, const std::string& key) {
  double d = r.bounded(v, key, limits::kLength);
  if (!(d > 0.0)) r.fail(key, "must be > 0 (zero-size primitive)");
  return d;
}

Object readObject(Reader& r, const json& o, const std::string& key, const Scene& s,
                  const std::filesystem::path& dir) {
  if (!o.is_object()) r.fail(key, "expected an object");
  Object ob;
  ob.where = r.file() + ": " + key;
  const std::string type = r.string(r.member(o, key, "type"), key + ".type");
  if (o.contains("material")) {
    ob.material = r.string(o["material"], key + ".material");
    if (!s.materialIndex.count(ob.material)) {
      std::string known;
      for (auto& [n, i] : s.materialIndex) known += (known.empty() ? "" : ", ") + echo(n);
      r.fail(key + ".material", "unknown material " + echo(ob.material) + " (defined: " + clipMessage(known, 400) + ")");
    }
  } else if (type != "mesh") {
    r.fail(key, "missing required key \"material\"");
  }
  if (o.contains("transform")) ob.transform = readTransform(r, o["transform"], key + ".transform");
  if (type == "quad") {
    r.checkKeys(o, key, {"type", "material", "transform", "vertices"});
    const json& v = r.member(o, key, "vertices");
    if (!v.is_array() || v.size() != 4) r.fail(key + ".vertices", "expected 4 points");
    for (int i = 0; i < 4; ++i) ob.quad[i] = r.vec3(v[i], key + ".vertices[" + std::to_string(i) + "]");
    ob.type = PrimitiveType::Quad;
  } else if (type == "box") {
    r.checkKeys(o, key, {"type", "material", "transform", "min", "max", "facing"});
    ob.type = PrimitiveType::Box;
    ob.min = r.vec3(r.member(o, key, "min"), key + ".min");
    ob.max = r.vec3(r.member(o, key, "max"), key + ".max");
    for (int i = 0; i < 3; ++i)
      if (!(ob.max[i] > ob.min[i])) r.fail(key, "max must exceed min on every axis (zero-size box)");
    if (o.contains("facing")) {
      std::string f = r.string(o["facing"], key + ".facing");
      if (f != "inward" && f != "outward") r.fail(key + ".facing", "expected \"inward\" or \"outward\"");
      ob.inward = f == "inward";
    }
  } else if (type == "disk") {
    r.checkKeys(o, key, {"type", "material", "transform", "center", "normal", "radius"});
    ob.type = PrimitiveType::Disk;
    ob.center = r.vec3(r.member(o, key, "center"), key + ".center");
    ob.normal = r.vec3(r.member(o, key, "normal"), key + ".normal");
    ob.radius = size(r, r.member(o, key, "radius"), key + ".radius");
    if (glm::length(ob.normal) == 0.0) r.fail(key + ".normal", "zero-length normal");
  } else if (type == "sphere") {
    r.checkKeys(o, key, {"type", "material", "transform", "center", "radius"});
    ob.type = PrimitiveType::Sphere;
    ob.center = r.vec3(r.member(o, key, "center"), key + ".center");
    ob.radius = size(r, r.member(o, key, "radius"), key + ".radius");
  } else if (type == "cylinder") {
    r.checkKeys(o, key, {"type", "material", "transform", "base", "axis", "radius", "height"});
    ob.type = PrimitiveType::Cylinder;
    ob.base = r.vec3(r.member(o, key, "base"), key + ".base");
    ob.axis = r.vec3(r.member(o, key, "axis"), key + ".axis");
    ob.radius = size(r, r.member(o, key, "radius"), key + ".radius");
    ob.height = size(r, r.member(o, key, "height"), key + ".height");
    if (glm::length(ob.axis) == 0.0) r.fail(key + ".axis", "zero-length axis");
  } else if (type == "mesh") {
    r.checkKeys(o, key, {"type", "material", "transform", "file"});
    ob.type = PrimitiveType::Mesh;
    ob.file = (dir / r.string(r.member(o, key, "file"), key + ".file")).string();
  } else {
    r.fail(key + ".type", "unknown object type " + echo(type) + " (valid: quad, box, disk, sphere, cylinder, mesh, mgf)");
  }
  return ob;
}

Camera readCamera(Reader& r, const json& c, const std::string& key) {
  if (!c.is_object()) r.fail(key, "expected an object");
  r.checkKeys(c, key, {"name", "eye", "look_at", "up", "fov_y_deg", "width", "height"});
  Camera cam;
  cam.name = r.string(r.member(c, key, "name"), key + ".name");
  // The name becomes file names (<name>.exr): no separators, no control bytes, not hidden (a leading
  // dot is where the output staging folder lives), and short enough for any file system.
  bool safe = !cam.name.empty() && cam.name.size() <= 200 && cam.name[0] != '.' &&
              std::none_of(cam.name.begin(), cam.name.end(), [](char ch) {
                return ch == '/' || ch == '\\' || static_cast<unsigned char>(ch) < 0x20;
              });
  if (!safe) r.fail(key + ".name", "must be a file-name-safe string (1-200 characters, no '/', '\\', control bytes or leading '.'), got " + echo(cam.name));
  cam.eye = r.vec3(r.member(c, key, "eye"), key + ".eye");
  cam.lookAt = r.vec3(r.member(c, key, "look_at"), key + ".look_at");
  if (c.contains("up")) cam.up = r.vec3(c["up"], key + ".up");
  if (c.contains("fov_y_deg")) cam.fovYDeg = r.bounded(c["fov_y_deg"], key + ".fov_y_deg", limits::kFovDeg);
  if (c.contains("width")) cam.width = r.integer(c["width"], key + ".width", limits::kImageSize);
  if (c.contains("height")) cam.height = r.integer(c["height"], key + ".height", limits::kImageSize);
  Vec3 f = cam.lookAt - cam.eye;
  if (glm::length(f) == 0.0) r.fail(key, "eye and look_at coincide");
  if (glm::length(glm::cross(f, cam.up)) == 0.0) r.fail(key + ".up", "parallel to the view direction");
  return cam;
}

Settings readSettings(Reader& r, const json& j) {
  if (!j.is_object()) r.fail("settings", "expected an object");
  r.checkKeys(j, "settings",
              {"eps", "max_level", "min_area", "rays_per_link", "max_iterations", "tolerance",
               "tessellation", "seed"});
  Settings st;
  namespace L = limits;
  if (j.contains("eps")) st.eps = r.bounded(j["eps"], "settings.eps", L::kEps);
  if (j.contains("max_level")) st.maxLevel = r.integer(j["max_level"], "settings.max_level", L::kMaxLevel);
  if (j.contains("min_area")) st.minArea = r.bounded(j["min_area"], "settings.min_area", L::kMinArea);
  if (j.contains("rays_per_link")) st.raysPerLink = r.integer(j["rays_per_link"], "settings.rays_per_link", L::kRaysPerLink);
  if (j.contains("max_iterations"))
    st.maxIterations = r.integer(j["max_iterations"], "settings.max_iterations", L::kMaxIterations);
  if (j.contains("tolerance")) st.tolerance = r.bounded(j["tolerance"], "settings.tolerance", L::kTolerance);
  if (j.contains("tessellation")) st.tessellation = r.integer(j["tessellation"], "settings.tessellation", L::kTessellation);
  if (j.contains("seed")) st.seed = static_cast<std::uint64_t>(r.integer(j["seed"], "settings.seed", L::kSeed));
  return st;
}

}  // namespace

Scene parseScene(const std::string& text, const std::string& path) {
  Scene s;
  s.path = path;
  s.name = path.empty() ? "default" : std::filesystem::path(path).stem().string();
  json j = parseStrictJson(text, path.empty() ? "<scene>" : path);
  Reader r(path.empty() ? "<scene>" : path, s);
  if (!j.is_object()) r.fail("(top level)", "expected a JSON object");
  r.checkKeys(j, "(top level)", {"materials", "objects", "cameras", "settings", "name"});
  if (j.contains("name")) s.name = r.string(j["name"], "name");
  readMaterials(r, r.member(j, "(top level)", "materials"), s);
  const json& objs = r.member(j, "(top level)", "objects");
  if (!objs.is_array() || objs.empty()) r.fail("objects", "expected a non-empty array");
  std::filesystem::path dir = path.empty() ? std::filesystem::current_path()
                                           : std::filesystem::path(path).parent_path();
  for (std::size_t i = 0; i < objs.size(); ++i) {
    const std::string key = "objects[" + std::to_string(i) + "]";
    if (objs[i].is_object() && objs[i].contains("type") && objs[i]["type"] == "mgf") {
      // An MGF file as one object: its geometry and materials join the scene, under the transform.
      r.checkKeys(objs[i], key, {"type", "file", "transform"});
      std::string file = (dir / r.string(r.member(objs[i], key, "file"), key + ".file")).string();
      Transform t;
      if (objs[i].contains("transform")) t = readTransform(r, objs[i]["transform"], key + ".transform");
      std::size_t before = s.objects.size();
      readMgf(file, s, t.matrix(), r.file() + ": " + key + ": ");
      if (s.objects.size() == before) r.fail(key + ".file", file + " holds no geometry (an empty MGF file adds nothing)");
      continue;
    }
    s.objects.push_back(readObject(r, objs[i], key, s, dir));
  }
  if (s.objects.size() > limits::kMaxObjects)
    r.fail("objects", std::to_string(s.objects.size()) + " objects, more than the limit of " +
                          std::to_string(limits::kMaxObjects));
  if (j.contains("cameras")) {
    const json& cams = j["cameras"];
    if (!cams.is_array()) r.fail("cameras", "expected an array");
    std::set<std::string> names;
    for (std::size_t i = 0; i < cams.size(); ++i) {
      Camera c = readCamera(r, cams[i], "cameras[" + std::to_string(i) + "]");
      if (!names.insert(c.name).second)
        r.fail("cameras[" + std::to_string(i) + "].name", "duplicate camera name " + echo(c.name));
      s.cameras.push_back(c);
    }
  }
  if (j.contains("settings")) s.settings = readSettings(r, j["settings"]);
  return s;
}

Scene loadScene(const std::string& path) {
  if (std::filesystem::path(path).extension() == ".mgf") return loadMgfScene(path);
  return parseScene(readInputFile(path, "scene file", limits::kMaxSceneBytes), path);
}

const char* primitiveName(PrimitiveType t) {
  switch (t) {
    case PrimitiveType::Quad: return "quad";
    case PrimitiveType::Box: return "box";
    case PrimitiveType::Disk: return "disk";
    case PrimitiveType::Sphere: return "sphere";
    case PrimitiveType::Cylinder: return "cylinder";
    case PrimitiveType::Cone: return "cone";
    case PrimitiveType::Ring: return "ring";
    case PrimitiveType::Polygon: return "polygon";
    default: return "mesh";
  }
}

glm::dmat4 Transform::matrix() const {
  if (explicitMatrix) return *explicitMatrix;
  glm::dmat4 m(1.0);
  m = glm::translate(m, translate);
  m = glm::rotate(m, glm::radians(rotateDeg.z), Vec3(0, 0, 1));
  m = glm::rotate(m, glm::radians(rotateDeg.y), Vec3(0, 1, 0));
  m = glm::rotate(m, glm::radians(rotateDeg.x), Vec3(1, 0, 0));
  m = glm::scale(m, scale);
  return m;
}

std::vector<std::uint32_t> emitterObjects(const Scene& scene) {
  std::vector<std::uint32_t> ids;
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    const std::string& m = scene.objects[i].material;
    if (!m.empty() && scene.materials[scene.materialIndex.at(m)].emitter()) ids.push_back(i);
  }
  return ids;
}

}  // namespace hr
