// What one element of a saved solution holds, for `glossyhr inspect` and the viewer's pick (p): its
// place, material and radiosity, the extension's coefficients and power, and its exitant radiant
// intensity (W/sr) as directional functions for a lobe surface: the host's Lambertian A B cos / pi,
// the extension's share, and their sum.
#pragma once
#include <hr/extension.h>
#include <hr/solution.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lobe_surface.h"

struct ElementReport {
  nlohmann::json json;  // the keys `inspect --json` prints
  std::string text;     // the lines `inspect` prints
};

ElementReport reportElement(const hr::Solution& s, const hr::Extension* ext, std::uint32_t id);

/// The element's exitant intensity: "intensity" (the sum, first), "lambertian_intensity",
/// "directional_intensity".
std::vector<LobeArray> elementLobe(const hr::Solution& s, const hr::Extension* ext, std::uint32_t id);
