// EXR (OpenEXR, 32-bit float RGB, linear radiance, plus a 32-bit "object_id" channel when known, so
// that comparisons can be masked by object) and PNG (stb_image_write, sRGB) writers.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <hr/input_file.h>
#include <hr/limits.h>
#include <hr/output.h>

namespace hr {

/// No output may hold NaN or Inf: a writer that meets one is looking at a bug upstream.
void requireFinite(const Image& img, const std::string& path) {
  for (float v : img.rgb)
    if (!std::isfinite(v)) throw std::runtime_error(path + ": refusing to write an image with a non-finite pixel");
}

void writeExr(const Image& img, const std::string& path) {
  requireFinite(img, path);
  writeAtomically(path, [&](const std::string& tmp) {
    Imf::Header header(img.width, img.height);
    const char* names[3] = {"R", "G", "B"};
    for (const char* n : names) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
    const bool ids = img.objectId.size() == std::size_t(img.width) * img.height;
    if (ids) header.channels().insert("object_id", Imf::Channel(Imf::UINT));
    Imf::OutputFile file(tmp.c_str(), header);
    Imf::FrameBuffer fb;
    for (int c = 0; c < 3; ++c)
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, (char*)(img.rgb.data() + c), 3 * sizeof(float),
                                     3 * sizeof(float) * img.width));
    if (ids)
      fb.insert("object_id", Imf::Slice(Imf::UINT, (char*)img.objectId.data(), sizeof(std::uint32_t),
                                        sizeof(std::uint32_t) * img.width));
    file.setFrameBuffer(fb);
    file.writePixels(img.height);
  });
}

Image readExr(const std::string& path) {
  Image img;
  checkInputFile(path, "EXR image", limits::kMaxImageBytes);
  try {
    Imf::InputFile file(path.c_str());
    auto dw = file.header().dataWindow();
    const long long w = (long long)dw.max.x - dw.min.x + 1, h = (long long)dw.max.y - dw.min.y + 1;
    if (!limits::kImageSize.contains(double(w)) || !limits::kImageSize.contains(double(h)))
      throw InputError(path + ": EXR image of " + std::to_string(w) + "x" + std::to_string(h) + " pixels, outside " +
                       limits::kImageSize.text() + " per side");
    img.width = int(w);
    img.height = int(h);
    img.rgb.assign(std::size_t(img.width) * img.height * 3, 0.0f);
    Imf::FrameBuffer fb;
    const char* names[3] = {"R", "G", "B"};
    char* base = (char*)(img.rgb.data()) - (dw.min.x + std::ptrdiff_t(dw.min.y) * img.width) * 3 * sizeof(float);
    for (int c = 0; c < 3; ++c)
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), 3 * sizeof(float), 3 * sizeof(float) * img.width));
    if (file.header().channels().findChannel("object_id")) {
      img.objectId.assign(std::size_t(img.width) * img.height, kNone);
      char* ib = (char*)(img.objectId.data()) - (dw.min.x + std::ptrdiff_t(dw.min.y) * img.width) * sizeof(std::uint32_t);
      fb.insert("object_id", Imf::Slice(Imf::UINT, ib, sizeof(std::uint32_t), sizeof(std::uint32_t) * img.width));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path + ": cannot read EXR: " + e.what());
  }
  return img;
}

void writePng8(const std::vector<unsigned char>& rgb, int width, int height, const std::string& path) {
  writeAtomically(path, [&](const std::string& tmp) {
    if (!stbi_write_png(tmp.c_str(), width, height, 3, rgb.data(), width * 3))
      throw std::runtime_error(path + ": cannot write PNG");
  });
}

double pngExposure(const Image& img) {
  double sumLog = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < img.rgb.size(); i += 3) {
    double l = luminance(Rgb(img.rgb[i], img.rgb[i + 1], img.rgb[i + 2]));
    if (l > 0.0) {
      sumLog += std::log(l);
      ++n;
    }
  }
  return n ? 0.18 / std::exp(sumLog / n) : 1.0;
}

unsigned char toneMap8(double radiance, double exposure) {
  double v = radiance * exposure;
  v = v / (1.0 + v);
  v = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
  return static_cast<unsigned char>(std::clamp(v * 255.0 + 0.5, 0.0, 255.0));
}

void writePng(const Image& img, const std::string& path) { writePng(img, path, pngExposure(img)); }

void writePng(const Image& img, const std::string& path, double exposure) {
  requireFinite(img, path);
  std::vector<unsigned char> px(img.rgb.size());
  for (std::size_t i = 0; i < img.rgb.size(); ++i) px[i] = toneMap8(img.rgb[i], exposure);
  writePng8(px, img.width, img.height, path);
}

}  // namespace hr
