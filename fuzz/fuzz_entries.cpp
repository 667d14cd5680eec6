// The fuzzed entry points (see fuzz_entries.h). Scenes are also tessellated, with the tessellation
// capped and only for scenes of at most a few hundred objects: the readers are the target, and a
// legal scene of a million spheres is slow, not wrong (a fuzzer that spends 50 ms per input on
// tessellating the Soda Shoppe explores little else).
#include "fuzz_entries.h"

#include <hr/geometry.h>
#include <hr/mgf.h>
#include <hr/solution.h>

#include <algorithm>

namespace ghrfuzz {
namespace {

std::string text(const std::uint8_t* d, std::size_t n) { return std::string(reinterpret_cast<const char*>(d), n); }

void tessellate(hr::Scene& s) {
  if (s.objects.size() > 500) return;
  s.settings.tessellation = std::min(s.settings.tessellation, 12);
  hr::TessellationReport rep;
  hr::buildPatches(s, rep);
}

template <class F>
int guarded(F&& f) {
  try {
    f();
  } catch (const hr::InputError&) {
    // The expected way to refuse bad input.
  }
  return 0;
}

}  // namespace

int sceneJson(const std::uint8_t* d, std::size_t n) {
  return guarded([&] {
    hr::Scene s = hr::parseScene(text(d, n), "fuzz.json");
    tessellate(s);
  });
}

int mgf(const std::uint8_t* d, std::size_t n) {
  return guarded([&] {
    hr::Scene s;
    hr::parseMgf(text(d, n), "fuzz.mgf", s);
    tessellate(s);
  });
}

int obj(const std::uint8_t* d, std::size_t n) {
  return guarded([&] { hr::parseMesh(text(d, n), "fuzz.obj", false); });
}

int ply(const std::uint8_t* d, std::size_t n) {
  return guarded([&] { hr::parseMesh(text(d, n), "fuzz.ply", false); });
}

int solution(const std::uint8_t* d, std::size_t n) {
  return guarded([&] {
    // Checksums off: random bytes would almost never pass them, and the validation behind them is
    // what must hold for a file whose checksums are right but whose content is not.
    hr::Solution s = hr::parseSolution(std::string_view(reinterpret_cast<const char*>(d), n), "fuzz.ghrs", false);
    for (std::uint32_t p = 0; p < s.patches.size(); ++p) {
      hr::Vec3 c = s.patches[p].poly.centroid();
      hr::interpolate(s, hr::locateLeaf(s, p, c), c);
    }
  });
}

Entry entry(const std::string& target) {
  if (target == "scene_json") return sceneJson;
  if (target == "mgf") return mgf;
  if (target == "obj") return obj;
  if (target == "ply") return ply;
  if (target == "solution") return solution;
  return nullptr;
}

}  // namespace ghrfuzz
