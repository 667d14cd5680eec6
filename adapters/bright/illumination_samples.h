// The Illumination Samples extension as the BRIGHT-like host loads it (--algorithm is).
#pragma once
#include <hr/extension.h>

#include <memory>

namespace adapters::bright {

std::unique_ptr<hr::Extension> makeIlluminationSamples();

}  // namespace adapters::bright
