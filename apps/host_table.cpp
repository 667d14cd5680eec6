// The host table, and what both hosts' front ends share: dropping an extension that no material of
// the scene needs (the run is then the diffuse host's to the bit).
#include "host_table.h"

#include <cstdio>

#include "host_front.h"

const std::vector<HostEntry>& hostTable() {
  static const std::vector<HostEntry> table = {
      {"bright", "BRIGHT-like: everything tessellated at load, quadtree elements, stored links, gathering",
       "diffuse, is, rc", "gather, shoot", solveBright},
      {"vision", "VISION-like: primitives kept whole, parameter-space elements, bounded radiosity, link-less shooting",
       "diffuse, is", "shoot", solveVision},
  };
  return table;
}

const HostEntry& findHost(const std::string& name) {
  std::string valid;
  for (const auto& h : hostTable()) {
    if (name == h.name) return h;
    valid += (valid.empty() ? "" : ", ") + std::string(h.name);
  }
  throw hr::InputError("--host: unknown host \"" + name + "\" (valid: " + valid + ")");
}

void dropUnneededExtension(HostJob& job) {
  if (!job.ext) return;
  // Only the effects a scene calls for: an extension that simulates none of its materials is not
  // loaded at all.
  for (const hr::Material& m : job.scene.materials)
    if (job.ext->simulates({m.diffuse, m.specular, m.exponent, m.emission})) return;
  if (!job.quiet)
    std::fprintf(stderr, "note: no material of this scene needs --algorithm %s: solved by the diffuse core alone\n",
                 job.algorithm.c_str());
  job.ext.reset();
}
