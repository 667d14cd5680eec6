// Extension table. "diffuse" is the core alone (no extension object, no hook is ever called).
#include "registry.h"

#include "bright/illumination_samples.h"
#include "bright/radiance_clustering.h"

namespace adapters {

const std::vector<ExtensionEntry>& extensionTable() {
  static const std::vector<ExtensionEntry> table = {
      {"diffuse", "plain diffuse hierarchical radiosity (no extension)", nullptr},
      {"is", "glossy global illumination with Illumination Samples (Stamminger et al., sections 3-4)",
       bright::makeIlluminationSamples},
      {"rc", "the Radiance Clustering baseline: immediate push of every link to the leaves (Sillion et al. 1995; paper 2.2)",
       bright::makeRadianceClustering},
  };
  return table;
}

const ExtensionEntry& findExtension(const std::string& name) {
  std::string valid;
  for (const auto& e : extensionTable()) {
    if (name == e.name) return e;
    valid += (valid.empty() ? "" : ", ") + std::string(e.name);
  }
  throw hr::InputError("--algorithm: unknown algorithm \"" + name + "\" (valid: " + valid + ")");
}

}  // namespace adapters
