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
    const std::uint32_t first = s.elements[e].firstChild;
    // Children's interiors are disjoint: the one child x lies strictly inside is the answer, found by
    // signs alone (a third of a three-lights render went to this descent, most of it in lengths).
    std::uint32_t best = first;
    bool found = false;
    for (std::uint32_t k = 0; k < 4 && !found; ++k)
      if (s.elements[first + k].poly.strictlyInside(x, n)) best = first + k, found = true;
    if (!found) {
      // On an edge or just outside every child (rounding): the child it is least outside of.
      double bestIn = -std::numeric_limits<double>::infinity();
      for (std::uint32_t k = 0; k < 4; ++k) {
        double in = s.elements[first + k].poly.insideness(x, n);
        if (in > bestIn) bestIn = in, best = first + k;
      }
    }
    e = best;
  }
  return e;
}

}  // namespace hr
