// Stills (see still.h).
#include "still.h"

#include <hr/output.h>

#include <array>
#include <cmath>

#include "window.h"

namespace view {

namespace {

/// The radiance times exposure each 8-bit value stands for: the centre of the code's interval, the
/// tone curve undone (sRGB, then Reinhard). 255 stands for its interval's middle, not infinity.
const std::array<double, 256>& codeValues() {
  static const std::array<double, 256> table = [] {
    std::array<double, 256> t{};
    for (int c = 0; c < 256; ++c) {
      double v = std::min(c, 254) / 255.0 + (c == 255 ? 0.75 / 255.0 : 0.0);
      double y = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
      t[std::size_t(c)] = y / (1.0 - y);
    }
    return t;
  }();
  return table;
}

}  // namespace

std::vector<unsigned char> downsampleStill(const std::vector<unsigned char>& samples, int w, int h, int k, double exposure) {
  const auto& value = codeValues();
  std::vector<unsigned char> out(std::size_t(w) * h * 3);
  const std::size_t W = std::size_t(w) * k;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        double sum = 0.0;
        for (int sy = 0; sy < k; ++sy)
          for (int sx = 0; sx < k; ++sx) sum += value[samples[3 * ((std::size_t(y) * k + sy) * W + std::size_t(x) * k + sx) + c]];
        // Back to radiance for the PNG writer's own curve (toneMap8 multiplies by the exposure again).
        out[3 * (std::size_t(y) * w + x) + c] = hr::toneMap8(sum / (k * k) / exposure, exposure);
      }
  return out;
}

std::vector<unsigned char> renderStill(vtkRenderer* r, int w, int h, int k, double exposure) {
  auto win = makeWindow(w * k, h * k, true);
  win->SetMultiSamples(0);
  win->AddRenderer(r);
  win->Render();
  std::vector<unsigned char> big = grabFrame(win);
  win->RemoveRenderer(r);
  win->Finalize();
  return downsampleStill(big, w, h, k, exposure);
}

}  // namespace view
