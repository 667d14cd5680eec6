// Point location in a solution snapshot (the smooth display reconstruction: reconstruct.cpp). Each
// host makes its own snapshot: bright/src/make_solution.cpp, vision_host/src/export.cpp.
#include <hr/solution.h>

#include <cmath>
#include <limits>

namespace hr {

std::uint32_t locateLeaf(const Solution& s, std::uint32_t patch, const Vec3& x) {
  std::uint32_t e = patch;
  const Vec3& n = s.patches[patch].normal;
  while (!s.elements[e].leaf()) {
    std::uint32_t best = s.elements[e].firstChild;
    double bestIn = -std::numeric_limits<double>::infinity();
    for (std::uint32_t k = 0; k < 4; ++k) {
      std::uint32_t c = s.elements[e].firstChild + k;
      double in = s.elements[c].poly.insideness(x, n);
      if (in > bestIn) {
        bestIn = in;
        best = c;
      }
      // Children's interiors are disjoint: the one child x lies strictly inside is the best, and the
      // rest need not be measured (a third of a three-lights render went to this descent).
      if (in > 0.0) break;
    }
    e = best;
  }
  return e;
}

}  // namespace hr
