// Joins the glossy extension to the BRIGHT-like core (base_radiosity). The extension needs nothing
// host-specific: the core already speaks hr/extension.h, so the adapter only makes the object. A
// host with another node model (the VISION-like one) puts its translation in its own adapter.
#include "illumination_samples.h"

#include <glossy/illumination_samples.h>

namespace adapters::bright {

std::unique_ptr<hr::Extension> makeIlluminationSamples() { return std::make_unique<glossy::IlluminationSamples>(); }

}  // namespace adapters::bright
