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
  // With the reference's variance image (the variance of each pixel's mean, per RGB channel, as
  // `reference` writes it): the reference's own noise as a relative RMSE, and relRmse with that
  // noise taken out (E[(a - b)^2] = (a - E b)^2 + Var b). The luminance's variance lies between the
  // channels' taken as independent and as fully correlated, hence a range; "lo" errors go with the
  // larger noise. A candidate better than the reference's noise shows 0.
  bool noiseKnown = false;
  double noiseRelRmseLo = 0.0, noiseRelRmseHi = 0.0;
  double relRmseDenoisedLo = 0.0, relRmseDenoisedHi = 0.0;
};

/// Throws hr::InputError when sizes differ, a mask is asked for and an image has no object ids, no
/// pixel is left to compare, a pixel is not finite or negative, or the reference is black (mean 0).
/// mask < 0: all pixels; exclude: objects whose pixels, and the pixels bordering them, are left out
/// (e.g. the light sources: their edges measure the pixel filters).
Metrics compare(const hr::Image& a, const hr::Image& b, long mask = -1, const std::string& nameA = "A",
                const std::string& nameB = "B", const std::vector<std::uint32_t>& exclude = {});

/// Adds the reference's noise to m, from B's variance image (same size, finite, >= 0; else
/// hr::InputError naming nameVar), over the same pixels as compare().
void addReferenceNoise(Metrics& m, const hr::Image& a, const hr::Image& b, const hr::Image& variance, long mask,
                       const std::vector<std::uint32_t>& exclude, const std::string& nameVar);

/// False colour of (a - b) / mean b: blue below, red above, white equal, saturating at +-range;
/// pixels outside the mask are grey.
void writeDifferencePng(const hr::Image& a, const hr::Image& b, const std::string& path, long mask = -1,
                        double range = 0.25, const std::vector<std::uint32_t>& exclude = {});

}  // namespace ref
