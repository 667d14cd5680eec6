// The scene report: primitives by type (and the source entities of an MGF import), total area,
// emitted power, bounding box, materials with their classification, and what an importer dropped.
#include "info_command.h"

#include <hr/geometry.h>

#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>

int runInfo(const std::string& path, bool asJson) {
  hr::Scene scene = hr::loadScene(path);
  std::map<std::string, std::size_t> types;
  for (const auto& o : scene.objects) ++types[hr::primitiveName(o.type)];
  hr::TessellationReport rep;
  std::vector<hr::Patch> patches = hr::buildPatches(scene, rep);
  hr::Aabb box;
  double area = 0.0;
  hr::Rgb power(0.0);
  std::vector<std::size_t> uses(scene.materials.size(), 0);
  for (const auto& p : patches) {
    for (int k = 0; k < p.poly.n; ++k) box.grow(p.poly.v[k]);
    area += p.area;
    power += hr::kPi * scene.materials[p.material].emission * p.area;
    ++uses[p.material];
  }
  auto kind = [](const hr::Material& m) {
    if (m.emitter()) return "emitter";
    if (m.glossy()) return "glossy";
    return hr::maxComponent(m.diffuse) > 0.0 ? "diffuse" : "black";
  };
  nlohmann::json j;
  j["scene"] = path;
  j["objects"] = scene.objects.size();
  j["primitives"] = types;
  j["source_entities"] = scene.entityCounts;
  j["patches"] = patches.size();
  j["dropped_zero_area_faces"] = rep.droppedZeroArea;
  j["total_area_m2"] = area;
  j["emitted_power_w"] = {power.x, power.y, power.z};
  j["bounding_box_m"] = {{"min", {box.lo.x, box.lo.y, box.lo.z}}, {"max", {box.hi.x, box.hi.y, box.hi.z}}};
  nlohmann::json mats = nlohmann::json::array();
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const hr::Material& m = scene.materials[i];
    mats.push_back({{"name", m.name}, {"class", kind(m)}, {"patches", uses[i]},
                    {"diffuse", {m.diffuse.x, m.diffuse.y, m.diffuse.z}},
                    {"specular", {m.specular.x, m.specular.y, m.specular.z}}, {"exponent", m.exponent},
                    {"emission", {m.emission.x, m.emission.y, m.emission.z}}});
  }
  j["materials"] = mats;
  j["dropped_or_approximated"] = scene.dropped;
  if (asJson) {
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("scene %s\n", path.c_str());
  std::printf("  objects: %zu (", scene.objects.size());
  bool first = true;
  for (const auto& [t, n] : types) std::printf("%s%zu %s", first ? "" : ", ", n, t.c_str()), first = false;
  std::printf(")\n");
  if (!scene.entityCounts.empty()) {
    std::printf("  source entities:");
    for (const auto& [t, n] : scene.entityCounts) std::printf(" %s %zu;", t.c_str(), n);
    std::printf("\n");
  }
  std::printf("  patches after tessellation: %zu (%zu zero-area faces dropped)\n", patches.size(), rep.droppedZeroArea);
  std::printf("  total area: %.6g m^2\n", area);
  std::printf("  emitted power: %.6g %.6g %.6g W (RGB)\n", power.x, power.y, power.z);
  std::printf("  bounding box: [%.4g, %.4g, %.4g] - [%.4g, %.4g, %.4g] m\n", box.lo.x, box.lo.y, box.lo.z, box.hi.x,
              box.hi.y, box.hi.z);
  std::printf("  materials: %zu\n", scene.materials.size());
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const hr::Material& m = scene.materials[i];
    std::printf("    %-32s %-8s rho_d %.3f %.3f %.3f  rho_s %.3f %.3f %.3f  n %-7.4g Le %.4g %.4g %.4g W/(m^2 sr)  (%zu patches)\n",
                m.name.c_str(), kind(m), m.diffuse.x, m.diffuse.y, m.diffuse.z, m.specular.x, m.specular.y, m.specular.z,
                m.exponent, m.emission.x, m.emission.y, m.emission.z, uses[i]);
  }
  for (const auto& d : scene.dropped) std::printf("  dropped or approximated: %s\n", d.c_str());
  return 0;
}
