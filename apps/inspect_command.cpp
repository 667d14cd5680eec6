// The inspect command (see inspect_command.h). The lobe is the node's whole exitant intensity, W/sr:
// the host's Lambertian A B cos / pi plus the extension's share, each also as an array of its own.
#include "inspect_command.h"

#include <hr/solution_view.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "extension_cli.h"
#include "lobe_surface.h"

namespace {

/// The leaf under point x: the patch whose plane is nearest among those whose polygon holds x's
/// projection, then its quadtree.
std::uint32_t leafAt(const hr::Solution& s, const hr::Vec3& x, const std::string& file) {
  std::uint32_t best = hr::kNone;
  double bestDist = std::numeric_limits<double>::infinity();
  for (std::uint32_t p = 0; p < s.patches.size(); ++p) {
    const hr::Patch& pt = s.patches[p];
    double h = glm::dot(x - pt.poly.v[0], pt.normal);
    hr::Vec3 y = x - h * pt.normal;
    if (pt.poly.insideness(y, pt.normal) < -1e-9 * pt.poly.radius()) continue;
    if (std::abs(h) < bestDist) bestDist = std::abs(h), best = p;
  }
  if (best == hr::kNone) throw hr::InputError("--point: no surface of " + file + " under that point");
  return hr::locateLeaf(s, best, x);
}

}  // namespace

int runInspect(const InspectArgs& a) {
  if ((a.element >= 0) == !a.point.empty()) throw hr::InputError("inspect: give --element or --point (one)");
  if (!a.out.empty() && std::filesystem::path(a.out).extension() != ".vtp")
    throw hr::InputError("-o: the lobe file must end in .vtp");
  hr::Solution sol = hr::loadSolution(a.solution);
  hr::SolutionView view(sol);
  std::unique_ptr<hr::Extension> ext = loadExtension(sol, view, a.solution);
  std::uint32_t id;
  if (a.element >= 0) {
    if (a.element >= static_cast<long long>(sol.elements.size()))
      throw hr::InputError("--element: " + std::to_string(a.element) + " is not an element of " + a.solution + " (0 to " +
                           std::to_string(sol.elements.size() - 1) + ")");
    id = static_cast<std::uint32_t>(a.element);
  } else {
    hr::Vec3 x(a.point[0], a.point[1], a.point[2]);
    if (!hr::allFinite(x)) throw hr::InputError("--point: finite numbers only");
    id = leafAt(sol, x, a.solution);
  }
  const hr::SolutionElement& e = sol.elements[id];
  const hr::Patch& p = sol.patches[e.patch];
  const hr::Material& m = sol.materials[p.material];
  const double area = e.poly.area();
  const hr::NodeId node{id};
  auto lambertian = [&](const hr::Vec3& d) { return e.radiosity * (area * std::max(0.0, glm::dot(p.normal, d)) / hr::kPi); };
  auto directional = [&](const hr::Vec3& d) { return ext ? ext->intensity(node, d) : hr::Rgb(0.0); };
  hr::Rgb power = ext ? ext->reflectedPower(node) : hr::Rgb(0.0);
  std::size_t coefficients = ext ? ext->coefficients(node) : 0;
  if (!a.out.empty())
    writeLobeSurface(a.out, {{"intensity", [&](const hr::Vec3& d) { return lambertian(d) + directional(d); }},
                             {"lambertian_intensity", lambertian},
                             {"directional_intensity", directional}});
  auto rgb = [](const hr::Rgb& c) { return nlohmann::json::array({c.x, c.y, c.z}); };
  nlohmann::json j;
  j["element"] = id;
  j["leaf"] = e.leaf();
  j["level"] = e.level;
  j["object"] = p.object;
  j["material"] = m.name;
  j["area_m2"] = area;
  j["normal"] = rgb(p.normal);
  j["radiosity_w_m2"] = rgb(e.radiosity);
  j["extension"] = sol.extension.name.empty() ? "none" : sol.extension.name;
  j["directional_coefficients"] = coefficients;
  j["directional_power_w"] = rgb(power);
  if (!a.out.empty()) j["lobe_file"] = a.out;
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("element %u (%s, level %u) of object %u, material \"%s\", area %.6g m^2\n", id, e.leaf() ? "leaf" : "inner",
                e.level, p.object, m.name.c_str(), area);
    std::printf("  radiosity (Lambertian part): %.6g %.6g %.6g W/m^2\n", e.radiosity.x, e.radiosity.y, e.radiosity.z);
    std::printf("  extension \"%s\": %zu directional coefficients, reflected power %.6g %.6g %.6g W\n",
                sol.extension.name.empty() ? "none" : sol.extension.name.c_str(), coefficients, power.x, power.y, power.z);
    if (!a.out.empty()) std::printf("  lobe (W/sr) written to %s\n", a.out.c_str());
  }
  return 0;
}
