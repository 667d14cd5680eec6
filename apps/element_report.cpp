// Element reports and lobes (see element_report.h).
#include "element_report.h"

#include <cstdio>

namespace {

std::string format(const char* fmt, auto... args) {
  char b[512];
  std::snprintf(b, sizeof b, fmt, args...);
  return b;
}

}  // namespace

ElementReport reportElement(const hr::Solution& s, const hr::Extension* ext, std::uint32_t id) {
  const hr::SolutionElement& e = s.elements[id];
  const hr::Patch& p = s.patches[e.patch];
  const hr::Material& m = s.materials[p.material];
  const double area = e.poly.area();
  const hr::NodeId node{id};
  hr::Rgb power = ext ? ext->reflectedPower(node) : hr::Rgb(0.0);
  std::size_t coefficients = ext ? ext->coefficients(node) : 0;
  const std::string extName = s.extension.name.empty() ? "none" : s.extension.name;
  auto rgb = [](const hr::Rgb& c) { return nlohmann::json::array({c.x, c.y, c.z}); };
  ElementReport r;
  nlohmann::json& j = r.json;
  j["element"] = id;
  j["leaf"] = e.leaf();
  j["level"] = e.level;
  j["object"] = p.object;
  j["material"] = m.name;
  j["area_m2"] = area;
  j["normal"] = rgb(p.normal);
  j["radiosity_w_m2"] = rgb(e.radiosity);
  j["extension"] = extName;
  j["directional_coefficients"] = coefficients;
  j["directional_power_w"] = rgb(power);
  r.text = format("element %u (%s, level %u) of object %u, material \"%s\", area %.6g m^2\n", id, e.leaf() ? "leaf" : "inner",
                  e.level, p.object, m.name.c_str(), area) +
           format("  radiosity (Lambertian part): %.6g %.6g %.6g W/m^2\n", e.radiosity.x, e.radiosity.y, e.radiosity.z) +
           format("  extension \"%s\": %zu directional coefficients, reflected power %.6g %.6g %.6g W\n", extName.c_str(),
                  coefficients, power.x, power.y, power.z);
  return r;
}

std::vector<LobeArray> elementLobe(const hr::Solution& s, const hr::Extension* ext, std::uint32_t id) {
  const hr::SolutionElement& e = s.elements[id];
  const hr::Vec3 n = s.patches[e.patch].normal;
  const hr::Rgb B = e.radiosity;
  const double area = e.poly.area();
  auto lambertian = [=](const hr::Vec3& d) { return B * (area * std::max(0.0, glm::dot(n, d)) / hr::kPi); };
  auto directional = [=](const hr::Vec3& d) { return ext ? ext->intensity(hr::NodeId{id}, d) : hr::Rgb(0.0); };
  return {{"intensity", [=](const hr::Vec3& d) { return lambertian(d) + directional(d); }},
          {"lambertian_intensity", lambertian},
          {"directional_intensity", directional}};
}
