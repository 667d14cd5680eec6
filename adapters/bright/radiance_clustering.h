// The Radiance Clustering baseline as the BRIGHT-like host loads it (--algorithm rc).
#pragma once
#include <hr/extension.h>

#include <memory>

namespace adapters::bright {

std::unique_ptr<hr::Extension> makeRadianceClustering();

}  // namespace adapters::bright
