// Image comparison of a candidate A against a reference B (linear radiance EXRs of the same size),
// optionally restricted to the pixels whose primary hit is one scene object. Metrics on luminance.
#pragma once
#include <hr/output.h>

#include <cstdint>
#include <string>
#include <vector>

namespace ref {

struct Metrics {
  std::size_t pixels = 0;
  double relRmse = 0.0;        // sqrt(mean (a - b)^2) / mean b
  double meanRelError = 0.0;   // mean |a - b| / b over pixels with b above 1e-3 of mean b
  double meanAbsError = 0.0;   // mean |a - b|, W/(m^2 sr)
  double maxAbsError = 0.0;    // W/(m^2 sr)
  double meanRatio = 0.0;      // mean a / mean b
  double meanA = 0.0, meanB = 0.0;
};

/// Throws hr::InputError when sizes differ, a mask is asked for and an image has no object ids, no
/// pixel is left to compare, a pixel is not finite or negative, or the reference is black (mean 0).
/// mask < 0: all pixels; exclude: objects whose pixels are left out (e.g. the light sources).
Metrics compare(const hr::Image& a, const hr::Image& b, long mask = -1, const std::string& nameA = "A",
                const std::string& nameB = "B", const std::vector<std::uint32_t>& exclude = {});

/// False colour of (a - b) / mean b: blue below, red above, white equal, saturating at +-range;
/// pixels outside the mask are grey.
void writeDifferencePng(const hr::Image& a, const hr::Image& b, const std::string& path, long mask = -1,
                        double range = 0.25, const std::vector<std::uint32_t>& exclude = {});

}  // namespace ref
