// Naming the first non-finite value after a sweep or pass. A NaN or Inf in the solution is always a
// bug (input is checked to be finite and bounded): the solve stops, and the message says where the
// value sits (host radiosity or the extension's light, element, object, material), so whoever
// debugs it starts at the right node instead of at "non-finite radiosity".
#include <cstdio>
#include <string>

#include "solver_state.h"

namespace hr::detail {

namespace {
std::string describe(const SolverState& s, std::uint32_t e) {
  const Patch& p = s.h.patches()[s.h.element(e).patch];
  char buf[160];
  std::snprintf(buf, sizeof buf, "element %u (object %u, material \"%s\")", e, p.object,
                s.scene.materials[p.material].name.c_str());
  return buf;
}
}  // namespace

std::string nonFiniteWhere(const SolverState& s, const std::string& when) {
  const auto& els = s.h.elements();
  for (std::uint32_t e = 0; e < els.size(); ++e)
    if (!allFinite(s.B[e]) || !allFinite(s.Et[e]))
      return "non-finite radiosity after " + when + ": the host's light at " + describe(s, e);
  if (s.ext)
    for (std::uint32_t e = 0; e < els.size(); ++e)
      if (els[e].leaf() && s.owned[e] && !allFinite(s.ext->reflectedPower(NodeId{e})))
        return "non-finite radiosity after " + when + ": the extension's (" + std::string(s.ext->name()) +
               ") reflected power at " + describe(s, e);
  return "non-finite radiosity after " + when + " (the residual; no element holds a non-finite value)";
}

}  // namespace hr::detail
