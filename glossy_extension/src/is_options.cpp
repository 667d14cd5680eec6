// Option parsing for the Illumination Samples extension: whole-string numbers only ("3x", "", "nan"
// are refused), ranges checked, options of another basis refused, each option at most once.
#include <glossy/is_options.h>

#include <charconv>
#include <cmath>
#include <map>

namespace glossy {

namespace {

[[noreturn]] void fail(const std::string& option, const std::string& why) { throw hr::InputError("--" + option + ": " + why); }

double parseDouble(const hr::OptionValue& v) {
  double x = 0.0;
  const char *b = v.value.data(), *e = b + v.value.size();
  auto [end, ec] = std::from_chars(b, e, x);
  if (ec != std::errc() || end != e || !std::isfinite(x)) fail(v.name, "not a finite number: '" + v.value + "'");
  return x;
}

int parseInt(const hr::OptionValue& v, int lo, int hi) {
  long long x = 0;
  const char *b = v.value.data(), *e = b + v.value.size();
  auto [end, ec] = std::from_chars(b, e, x);
  if (ec != std::errc() || end != e || x < lo || x > hi)
    fail(v.name, "must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got '" + v.value + "'");
  return static_cast<int>(x);
}

/// The basis an option belongs to; with --basis auto every basis's options apply (to the materials
/// that get that basis).
const char* owner(const std::string& name) {
  if (name == "dir-eps" || name == "dir-min-level" || name == "dir-max-level") return "haar";
  if (name == "tetra-level") return "tetra";
  if (name == "sh-order") return "sh";
  return nullptr;
}

}  // namespace

BasisSpec defaultIsBasis() {
  BasisSpec b;
  b.basis = Basis::Haar;
  b.haar.eps = 0.5;
  b.haar.minLevel = 1;
  b.haar.maxLevel = 3;
  b.haar.refiner = Refiner::Relative;
  b.tetraLevel = 3;
  b.shOrder = 8;
  return b;
}

std::vector<hr::OptionSpec> isOptionSpecs() {
  return {
      {"basis", "directional basis of glossy exitant light: haar (adaptive, default), tetra, sh, or auto (per material "
                "from its exponent; docs/directional.md)"},
      {"dir-eps", "haar: relative refinement threshold of the distributions (> 0; default 0.5)"},
      {"dir-min-level", "haar: minimum subdivision level (0-8, default 1)"},
      {"dir-max-level", "haar: maximum subdivision level (0-8, at least dir-min-level), a hard cap for every material when "
                        "given; default per material from its lobe width sqrt(2/n): the coarsest level whose cells are no "
                        "wider, within 3-5 (n = 60 -> 3, 300 -> 4, 500 -> 5; docs/glossy.md)"},
      {"tetra-level", "tetra: subdivision level of the tetrahedron (0-8, default 3)"},
      {"sh-order", "sh: spherical harmonics order, bands 0 to order-1 (1-32, default 8)"},
      {"reflection-refine", "on (default), cell or off: the host's oracle splits a glossy receiver, or its sender, seen "
                            "from directions further apart than the receiver's lobe; cell: than the lobe or the "
                            "material's Haar cell, whichever is wider (fewer links, a blurrier near reflection; "
                            "docs/glossy.md)"},
      {"sender-extent", "on (default) or off: a sample whose sender is seen wider than the receiver's lobe is "
                        "reflected as the sender's disk (spread over up to 8 directions), not as one lobe about "
                        "its centre (docs/glossy.md)"},
      {"exact-highlights", "on (default) or off: the display reflects each glossy leaf's brightest incident "
                           "samples (at most 16, each at least 1/64 of its light, a flat sender's pieces joined "
                           "where they would fall short) exactly at the point shown, in "
                           "place of their mean over the stored cell it reads; off shows the stored distribution "
                           "alone, as the paper (docs/glossy.md, \"Highlights at display\")"},
  };
}

BasisSpec parseIsOptions(const std::vector<hr::OptionValue>& values) {
  std::map<std::string, const hr::OptionValue*> given;
  std::string valid;
  for (const auto& s : isOptionSpecs()) valid += (valid.empty() ? "" : ", ") + s.name;
  for (const auto& v : values) {
    bool known = false;
    for (const auto& s : isOptionSpecs()) known = known || s.name == v.name;
    if (!known) fail(v.name, "not an option of --algorithm is (valid: " + valid + ")");
    if (!given.emplace(v.name, &v).second) fail(v.name, "given twice");
  }
  BasisSpec b = defaultIsBasis();
  if (auto it = given.find("basis"); it != given.end()) {
    const std::string& name = it->second->value;
    b.automatic = name == "auto";
    if (!b.automatic && name != "haar" && name != "tetra" && name != "sh")
      fail("basis", "unknown basis '" + name + "' (valid: haar, tetra, sh, auto)");
    if (!b.automatic) b.basis = parseBasis(name);
  }
  for (const auto& [name, v] : given) {
    const char* o = owner(name);
    if (o && !b.automatic && std::string(o) != basisName(b.basis))
      fail(name, std::string("applies to --basis ") + o + " only (the basis is " + basisName(b.basis) + ")");
  }
  if (auto it = given.find("dir-eps"); it != given.end()) {
    b.haar.eps = parseDouble(*it->second);
    if (!(b.haar.eps > 0.0)) fail("dir-eps", "must be > 0, got " + it->second->value);
  }
  if (auto it = given.find("dir-min-level"); it != given.end()) b.haar.minLevel = parseInt(*it->second, 0, kMaxDirLevel);
  if (auto it = given.find("dir-max-level"); it != given.end()) {
    b.haar.maxLevel = parseInt(*it->second, 0, kMaxDirLevel);
    b.haarLevelGiven = true;
  }
  if (b.haar.minLevel > b.haar.maxLevel) {
    bool minGiven = given.count("dir-min-level") != 0;
    fail(minGiven ? "dir-min-level" : "dir-max-level",
         "--dir-min-level (" + std::to_string(b.haar.minLevel) + ") must not exceed --dir-max-level (" +
             std::to_string(b.haar.maxLevel) + ")");
  }
  if (auto it = given.find("tetra-level"); it != given.end()) b.tetraLevel = parseInt(*it->second, 0, TetraMesh::kMaxLevel);
  if (auto it = given.find("sh-order"); it != given.end()) b.shOrder = parseInt(*it->second, 1, ShDistribution::kMaxOrder);
  return b;
}

ReflectionRefine parseReflectionRefine(const std::vector<hr::OptionValue>& values) {
  for (const auto& v : values)
    if (v.name == "reflection-refine") {
      if (v.value == "on") return ReflectionRefine::Lobe;
      if (v.value == "cell") return ReflectionRefine::Cell;
      if (v.value == "off") return ReflectionRefine::Off;
      fail(v.name, "must be on, cell or off, got '" + v.value + "'");
    }
  return ReflectionRefine::Lobe;
}

bool parseOnOff(const std::vector<hr::OptionValue>& values, const std::string& name) {
  for (const auto& v : values)
    if (v.name == name) {
      if (v.value == "on") return true;
      if (v.value == "off") return false;
      fail(v.name, "must be on or off, got '" + v.value + "'");
    }
  return true;
}

void validateIsBasis(const BasisSpec& b, const std::string& context) {
  auto bad = [&](const std::string& why) { throw hr::InputError(context + ": " + why); };
  if (b.basis != Basis::Haar && b.basis != Basis::Tetra && b.basis != Basis::Sh) bad("unknown basis");
  if (!(b.haar.eps > 0.0) || !std::isfinite(b.haar.eps)) bad("bad dir-eps");
  if (b.haar.minLevel < 0 || b.haar.maxLevel > kMaxDirLevel || b.haar.minLevel > b.haar.maxLevel) bad("bad Haar levels");
  if (b.tetraLevel < 0 || b.tetraLevel > TetraMesh::kMaxLevel) bad("bad tetra-level");
  if (b.shOrder < 1 || b.shOrder > ShDistribution::kMaxOrder) bad("bad sh-order");
}

}  // namespace glossy
