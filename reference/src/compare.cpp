// Comparison metrics and the false-colour difference image. Images that cannot be measured (a
// non-finite or negative pixel, a reference without light) are refused: relative errors against them
// would print as 0 or -inf and look like an answer.
#include <ref/compare.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace ref {

namespace {

/// The pixels compared. An excluded object takes the pixels bordering it along (8-neighbours): a
/// pixel whose centre shows the ceiling may hold a sliver of the light panel beside it, and a sliver
/// of a light 30 times brighter than the ceiling measures the pixel filters, not the solutions.
std::vector<char> selection(const hr::Image& img, long mask, const std::vector<std::uint32_t>& exclude) {
  const int W = img.width, H = img.height;
  std::vector<char> keep(std::size_t(W) * H, 1);
  if (mask < 0 && exclude.empty()) return keep;
  auto excluded = [&](std::size_t i) {
    return std::find(exclude.begin(), exclude.end(), img.objectId[i]) != exclude.end();
  };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      std::size_t i = std::size_t(y) * W + x;
      if (mask >= 0 && img.objectId[i] != static_cast<std::uint32_t>(mask)) keep[i] = 0;
      if (exclude.empty() || !excluded(i)) continue;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (x + dx >= 0 && x + dx < W && y + dy >= 0 && y + dy < H) keep[std::size_t(y + dy) * W + x + dx] = 0;
    }
  return keep;
}

double lum(const hr::Image& img, std::size_t i) {
  return hr::luminance(hr::Rgb(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]));
}

void checkPair(const hr::Image& a, const hr::Image& b, bool masked, const std::string& nameA, const std::string& nameB) {
  if (a.width != b.width || a.height != b.height)
    throw hr::InputError(nameA + " is " + std::to_string(a.width) + "x" + std::to_string(a.height) + " but " + nameB +
                         " is " + std::to_string(b.width) + "x" + std::to_string(b.height) + ": images must have the same size");
  if (masked && a.objectId.size() != std::size_t(a.width) * a.height)
    throw hr::InputError("--mask/--exclude: " + nameA + " has no object_id channel");
  for (const auto* img : {&a, &b}) {
    const std::string& name = img == &a ? nameA : nameB;
    for (std::size_t i = 0; i < img->rgb.size(); ++i)
      if (!std::isfinite(img->rgb[i]) || img->rgb[i] < 0.0f) {
        std::size_t p = i / 3;
        throw hr::InputError(name + ": pixel (" + std::to_string(p % std::size_t(img->width)) + ", " +
                             std::to_string(p / std::size_t(img->width)) + ") holds " + std::to_string(img->rgb[i]) +
                             ": radiance must be finite and >= 0 to be compared");
      }
  }
}

}  // namespace

Metrics compare(const hr::Image& a, const hr::Image& b, long mask, const std::string& nameA, const std::string& nameB,
                const std::vector<std::uint32_t>& exclude) {
  checkPair(a, b, mask >= 0 || !exclude.empty(), nameA, nameB);
  const std::size_t P = std::size_t(a.width) * a.height;
  const std::vector<char> keep = selection(a, mask, exclude);
  Metrics m;
  double se = 0.0, sae = 0.0;
  for (std::size_t i = 0; i < P; ++i) {
    if (!keep[i]) continue;
    double va = lum(a, i), vb = lum(b, i);
    ++m.pixels;
    m.meanA += va, m.meanB += vb;
    se += (va - vb) * (va - vb);
    sae += std::abs(va - vb);
    m.maxAbsError = std::max(m.maxAbsError, std::abs(va - vb));
  }
  if (m.pixels == 0) throw hr::InputError("--mask: no pixel of object " + std::to_string(mask) + " in " + nameA);
  m.meanA /= double(m.pixels), m.meanB /= double(m.pixels);
  if (!(m.meanB > 0.0))
    throw hr::InputError(nameB + ": the reference is black" + std::string(mask >= 0 ? " over the masked pixels" : "") +
                         ": errors relative to it are undefined");
  m.meanAbsError = sae / double(m.pixels);
  m.relRmse = m.meanB > 0.0 ? std::sqrt(se / double(m.pixels)) / m.meanB : 0.0;
  m.meanRatio = m.meanB > 0.0 ? m.meanA / m.meanB : 0.0;
  double rel = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < P; ++i) {
    if (!keep[i]) continue;
    double vb = lum(b, i);
    if (vb <= 1e-3 * m.meanB) continue;
    rel += std::abs(lum(a, i) - vb) / vb;
    ++n;
  }
  m.meanRelError = n ? rel / double(n) : 0.0;
  return m;
}

void addReferenceNoise(Metrics& m, const hr::Image& a, const hr::Image& b, const hr::Image& variance, long mask,
                       const std::vector<std::uint32_t>& exclude, const std::string& nameVar) {
  checkPair(a, variance, false, "the candidate", nameVar);
  const std::size_t P = std::size_t(a.width) * a.height;
  const std::vector<char> keep = selection(a, mask, exclude);
  // Luminance is linear: its weights are its values on the unit colours.
  const double w[3] = {hr::luminance(hr::Rgb(1, 0, 0)), hr::luminance(hr::Rgb(0, 1, 0)), hr::luminance(hr::Rgb(0, 0, 1))};
  double se = 0.0, independent = 0.0, correlated = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < P; ++i) {
    if (!keep[i]) continue;
    const double d = lum(a, i) - lum(b, i);
    se += d * d;
    double sumW2V = 0.0, sumWS = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double v = variance.rgb[3 * i + std::size_t(c)];
      sumW2V += w[c] * w[c] * v;
      sumWS += w[c] * std::sqrt(v);
    }
    independent += sumW2V, correlated += sumWS * sumWS;
    ++n;
  }
  const double N = double(std::max<std::size_t>(n, 1)), B = m.meanB;
  m.noiseKnown = true;
  m.noiseRelRmseLo = std::sqrt(independent / N) / B;
  m.noiseRelRmseHi = std::sqrt(correlated / N) / B;
  m.relRmseDenoisedLo = std::sqrt(std::max(0.0, se - correlated) / N) / B;
  m.relRmseDenoisedHi = std::sqrt(std::max(0.0, se - independent) / N) / B;
}

void writeDifferencePng(const hr::Image& a, const hr::Image& b, const std::string& path, long mask, double range,
                        const std::vector<std::uint32_t>& exclude) {
  Metrics m = compare(a, b, mask, "A", "B", exclude);
  const std::size_t P = std::size_t(a.width) * a.height;
  const std::vector<char> keep = selection(a, mask, exclude);
  std::vector<unsigned char> px(3 * P, 128);
  for (std::size_t i = 0; i < P; ++i) {
    if (!keep[i]) continue;
    double t = m.meanB > 0.0 ? std::clamp((lum(a, i) - lum(b, i)) / (m.meanB * range), -1.0, 1.0) : 0.0;
    // White at 0, towards red (A brighter) or blue (A darker).
    double r = t < 0.0 ? 1.0 + t : 1.0, g = 1.0 - std::abs(t), bl = t > 0.0 ? 1.0 - t : 1.0;
    px[3 * i] = static_cast<unsigned char>(255.0 * r + 0.5);
    px[3 * i + 1] = static_cast<unsigned char>(255.0 * g + 0.5);
    px[3 * i + 2] = static_cast<unsigned char>(255.0 * bl + 0.5);
  }
  hr::writePng8(px, a.width, a.height, path);
}

}  // namespace ref
