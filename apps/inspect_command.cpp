// The inspect command (see inspect_command.h). The lobe is the node's whole exitant intensity, W/sr:
// the host's Lambertian A B cos / pi plus the extension's share, each also as an array of its own.
#include "inspect_command.h"

#include <hr/solution_view.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "extension_cli.h"
#include "element_report.h"

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
  if (!a.out.empty()) writeLobeSurface(a.out, elementLobe(sol, ext.get(), id));
  ElementReport r = reportElement(sol, ext.get(), id);
  if (!a.out.empty()) r.json["lobe_file"] = a.out;
  if (a.json) {
    std::printf("%s\n", r.json.dump(2).c_str());
  } else {
    std::printf("%s", r.text.c_str());
    if (!a.out.empty()) std::printf("  lobe (W/sr) written to %s\n", a.out.c_str());
  }
  return 0;
}
