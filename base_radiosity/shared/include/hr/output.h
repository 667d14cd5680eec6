// Writers for everything the solver leaves on disk. Every writer goes through writeAtomically():
// the bytes land in a temporary file next to the target, which is renamed only when complete.
#pragma once
#include <hr/extension.h>
#include <hr/solution.h>
#include <hr/solve.h>

#include <functional>
#include <string>
#include <vector>

namespace hr {

void writeAtomically(const std::string& path, const std::function<void(const std::string& tmpPath)>& write);
void writeFileAtomically(const std::string& path, const std::string& bytes);

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // linear radiance, W/(m^2 sr), row-major from the top
  std::vector<std::uint32_t> objectId;  // scene object per pixel, kNone for background
};

/// Radiance of a solution leaf toward the eye. The display hook of an extension takes precedence;
/// the default is the smooth diffuse reconstruction B/pi.
using DisplayFn = std::function<Rgb(std::uint32_t leaf, const Vec3& hitPoint, const Vec3& toEye)>;

/// Casts samplesPerAxis^2 primary rays per pixel (a regular grid) through Embree and shades from the
/// stored solution, and 9 times as many where they differ (edges, shadows, highlights); pixels hold
/// averages (W/(m^2 sr)), object ids come from the pixel centre.
Image render(const Solution& s, const Camera& cam, const DisplayFn& display = nullptr, int samplesPerAxis = 3);
/// The same with the run's extension, loaded (its radiance added, smooth per display vertex); a null
/// extension renders the host's light alone.
Image render(const Solution& s, const Camera& cam, const Extension* ext);
void writeExr(const Image& img, const std::string& path);
Image readExr(const std::string& path);
/// sRGB PNG, tone-mapped by a global exposure (key 0.18 over the log-average luminance) and
/// Reinhard's x/(1+x): see README "Outputs".
void writePng(const Image& img, const std::string& path);
/// The same with a given exposure (the viewer keeps one for a whole session).
void writePng(const Image& img, const std::string& path, double exposure);
/// writePng's exposure for an image: 0.18 over its log-average luminance (1 for a black image).
double pngExposure(const Image& img);
/// writePng's tone curve for one channel: radiance (W/(m^2 sr)) times exposure, Reinhard, sRGB, 8 bits.
unsigned char toneMap8(double radiance, double exposure);
/// 8-bit RGB pixels as they are (no tone mapping): false-colour images.
void writePng8(const std::vector<unsigned char>& rgb, int width, int height, const std::string& path);

/// VTK XML PolyData of the leaf elements (see README "Outputs" for the arrays); with the run's
/// extension, also its coefficients and reflected power per leaf.
void writeVtp(const Solution& s, const std::string& path, const Extension* ext = nullptr);

struct RunInfo {
  std::string scene, host = "bright", algorithm = "diffuse";
  double eps = 0, maxImbalance = 0.02;
  int maxLevel = 0, threads = 1, raysPerLink = 0;
  std::uint64_t seed = 0;
  std::vector<std::pair<std::string, double>> extension;  // the extension's own figures
  std::vector<std::pair<std::string, std::string>> extensionText;  // and its choices, by name
};
std::string statsJson(const RunInfo& run, const SolveStats& st, std::size_t peakRssBytes);
std::size_t peakRssBytes();
/// The resident memory in use now (VmRSS), bytes; 0 where /proc is not available.
std::size_t currentRssBytes();
/// Heap the allocator holds free for reuse (glibc mallinfo2), bytes.
std::size_t freeHeapBytes();

}  // namespace hr
