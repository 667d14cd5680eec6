// Joins the Radiance Clustering baseline to the BRIGHT-like core. As for Illumination Samples, the
// core already speaks hr/extension.h (its gather hook runs top-down, which the immediate push needs),
// so the adapter only makes the object.
#include "radiance_clustering.h"

#include <glossy/radiance_clustering.h>

namespace adapters::bright {

std::unique_ptr<hr::Extension> makeRadianceClustering() { return std::make_unique<glossy::RadianceClustering>(); }

}  // namespace adapters::bright
