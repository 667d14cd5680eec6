// Camera path files (see camera_path.h). Every value is checked against the limits table the scene
// readers use, and a message names the file and the key, so a hand-written path is easy to fix.
#include "camera_path.h"

#include <hr/input_file.h>
#include <hr/json_strict.h>
#include <hr/limits.h>

#include <cmath>
#include <set>

namespace view {

namespace {

using nlohmann::json;

constexpr std::uint64_t kMaxPathBytes = 16ull << 20;
constexpr std::size_t kMaxKeyframes = 100000;
constexpr hr::limits::Range kFps{"fps", 1e-3, 1000.0};
constexpr hr::limits::Range kTime{"time", -1e7, 1e7};
constexpr int kMaxFrames = 1000000;

[[noreturn]] void fail(const std::string& file, const std::string& key, const std::string& why) {
  throw hr::InputError(file + ": " + key + ": " + why);
}

double number(const json& j, const std::string& file, const std::string& key, const hr::limits::Range& r) {
  if (!j.is_number()) fail(file, key, "expected a number");
  double v = j.get<double>();
  if (!hr::limits::within(v, r)) fail(file, key, std::to_string(v) + " is outside " + r.text());
  return v;
}

hr::Vec3 vec3(const json& j, const std::string& file, const std::string& key) {
  if (!j.is_array() || j.size() != 3) fail(file, key, "expected [x, y, z]");
  hr::Vec3 v;
  for (int k = 0; k < 3; ++k) v[k] = number(j[k], file, key + "[" + std::to_string(k) + "]", hr::limits::kCoordinate);
  return v;
}

void onlyKeys(const json& j, const std::set<std::string>& allowed, const std::string& file, const std::string& where) {
  for (const auto& [k, v] : j.items())
    if (!allowed.count(k)) fail(file, where + k, "unknown key");
}

/// Cubic Hermite between a and b with tangents ma, mb (per unit of s in [0, 1]).
template <class T>
T hermite(const T& a, const T& b, const T& ma, const T& mb, double s) {
  double s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * a + (s3 - 2 * s2 + s) * ma + (-2 * s3 + 3 * s2) * b + (s3 - s2) * mb;
}

}  // namespace

int CameraPath::frameCount() const {
  if (keys.empty()) return 0;
  double n = std::floor(duration() * fps + 1e-9) + 1.0;
  return n > kMaxFrames ? kMaxFrames + 1 : static_cast<int>(n);
}

void validateCameraPath(const CameraPath& p, const std::string& file) {
  if (p.keys.empty()) fail(file, "keyframes", "at least one keyframe is needed");
  if (p.keys.size() > kMaxKeyframes) fail(file, "keyframes", "more than " + std::to_string(kMaxKeyframes));
  if (!hr::limits::within(p.fps, kFps)) fail(file, "fps", std::to_string(p.fps) + " is outside " + kFps.text());
  for (const char* k : {"width", "height"}) {
    int v = std::string(k) == "width" ? p.width : p.height;
    if (v != 0 && !hr::limits::within(v, hr::limits::kImageSize))
      fail(file, k, std::to_string(v) + " is outside " + hr::limits::kImageSize.text());
  }
  for (std::size_t i = 0; i < p.keys.size(); ++i) {
    const Keyframe& k = p.keys[i];
    std::string at = "keyframes[" + std::to_string(i) + "].";
    if (!hr::limits::within(k.time, kTime)) fail(file, at + "time", "outside " + kTime.text());
    if (i > 0 && !(k.time > p.keys[i - 1].time)) fail(file, at + "time", "times must increase strictly");
    if (!hr::allFinite(k.eye) || !hr::allFinite(k.lookAt) || !hr::allFinite(k.up)) fail(file, at + "eye", "finite numbers only");
    if (!(glm::length(k.lookAt - k.eye) > 0.0)) fail(file, at + "look_at", "must differ from eye");
    if (!(glm::length(glm::cross(glm::normalize(k.lookAt - k.eye), k.up)) > 1e-6 * glm::length(k.up)))
      fail(file, at + "up", "must not be zero or parallel to the view");
    if (!hr::limits::within(k.fovYDeg, hr::limits::kFovDeg))
      fail(file, at + "fov_y_deg", std::to_string(k.fovYDeg) + " is outside " + hr::limits::kFovDeg.text());
  }
  if (p.frameCount() > kMaxFrames) fail(file, "fps", "the path would take more than " + std::to_string(kMaxFrames) + " frames");
}

CameraPath parseCameraPath(const std::string& text, const std::string& file) {
  json j = hr::parseStrictJson(text, file);
  if (!j.is_object()) fail(file, "(top level)", "expected an object with \"keyframes\"");
  onlyKeys(j, {"keyframes", "fps", "width", "height"}, file, "");
  CameraPath p;
  if (!j.contains("keyframes")) fail(file, "keyframes", "missing");
  if (j.contains("fps")) p.fps = number(j["fps"], file, "fps", kFps);
  if (j.contains("width")) p.width = int(number(j["width"], file, "width", hr::limits::kImageSize));
  if (j.contains("height")) p.height = int(number(j["height"], file, "height", hr::limits::kImageSize));
  const json& ks = j["keyframes"];
  if (!ks.is_array()) fail(file, "keyframes", "expected an array of keyframes");
  if (ks.size() > kMaxKeyframes) fail(file, "keyframes", "more than " + std::to_string(kMaxKeyframes));
  for (std::size_t i = 0; i < ks.size(); ++i) {
    std::string at = "keyframes[" + std::to_string(i) + "].";
    const json& k = ks[i];
    if (!k.is_object()) fail(file, at.substr(0, at.size() - 1), "expected an object");
    onlyKeys(k, {"time", "eye", "look_at", "up", "fov_y_deg"}, file, at);
    for (const char* req : {"time", "eye", "look_at"})
      if (!k.contains(req)) fail(file, at + req, "missing");
    Keyframe f;
    f.time = number(k["time"], file, at + "time", kTime);
    f.eye = vec3(k["eye"], file, at + "eye");
    f.lookAt = vec3(k["look_at"], file, at + "look_at");
    if (k.contains("up")) f.up = vec3(k["up"], file, at + "up");
    if (k.contains("fov_y_deg")) f.fovYDeg = number(k["fov_y_deg"], file, at + "fov_y_deg", hr::limits::kFovDeg);
    p.keys.push_back(f);
  }
  validateCameraPath(p, file);
  return p;
}

CameraPath loadCameraPath(const std::string& path) {
  return parseCameraPath(hr::readInputFile(path, "camera path", kMaxPathBytes), path);
}

std::string cameraPathJson(const CameraPath& p) {
  auto v = [](const hr::Vec3& x) { return json::array({x.x, x.y, x.z}); };
  json j;
  j["fps"] = p.fps;
  if (p.width > 0) j["width"] = p.width;
  if (p.height > 0) j["height"] = p.height;
  j["keyframes"] = json::array();
  for (const Keyframe& k : p.keys)
    j["keyframes"].push_back({{"time", k.time}, {"eye", v(k.eye)}, {"look_at", v(k.lookAt)}, {"up", v(k.up)}, {"fov_y_deg", k.fovYDeg}});
  return j.dump(1) + "\n";
}

hr::Camera cameraAt(const CameraPath& p, double t, int width, int height) {
  const auto& k = p.keys;
  hr::Camera c;
  c.name = "walkthrough";
  c.width = width;
  c.height = height;
  std::size_t i = 0;
  if (k.size() == 1 || t <= k.front().time) {
    i = 0, t = k.front().time;
  } else if (t >= k.back().time) {
    i = k.size() - 2, t = k.back().time;
  } else {
    while (i + 2 < k.size() && t >= k[i + 1].time) ++i;
  }
  const Keyframe& a = k[i];
  if (k.size() == 1) {
    c.eye = a.eye, c.lookAt = a.lookAt, c.up = a.up, c.fovYDeg = a.fovYDeg;
    return c;
  }
  const Keyframe& b = k[i + 1];
  const double h = b.time - a.time, s = std::clamp((t - a.time) / h, 0.0, 1.0);
  // Catmull-Rom tangents over non-uniform times, scaled to the segment; one-sided at the ends.
  auto tangent = [&](std::size_t j, auto get) {
    std::size_t lo = j > 0 ? j - 1 : j, hi = j + 1 < k.size() ? j + 1 : j;
    return (get(k[hi]) - get(k[lo])) * (h / (k[hi].time - k[lo].time));
  };
  auto along = [&](auto get) { return hermite(get(a), get(b), tangent(i, get), tangent(i + 1, get), s); };
  c.eye = along([](const Keyframe& f) { return f.eye; });
  c.lookAt = along([](const Keyframe& f) { return f.lookAt; });
  hr::Vec3 up = along([](const Keyframe& f) { return f.up; });
  c.fovYDeg = std::clamp(along([](const Keyframe& f) { return f.fovYDeg; }), hr::limits::kFovDeg.lo, hr::limits::kFovDeg.hi);
  // The spline may overshoot into a degenerate frame between keys: fall back to the nearer key's.
  hr::Vec3 f = c.lookAt - c.eye;
  if (!(glm::length(f) > 0.0)) c.lookAt = c.eye + (s < 0.5 ? a.lookAt - a.eye : b.lookAt - b.eye);
  f = glm::normalize(c.lookAt - c.eye);
  c.up = glm::length(glm::cross(f, up)) > 1e-6 * glm::length(up) ? glm::normalize(up) : (s < 0.5 ? a.up : b.up);
  return c;
}

}  // namespace view
