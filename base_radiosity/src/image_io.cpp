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
#include <hr/output.h>

namespace hr {

void writeExr(const Image& img, const std::string& path) {
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
  try {
    Imf::InputFile file(path.c_str());
    auto dw = file.header().dataWindow();
    img.width = dw.max.x - dw.min.x + 1;
    img.height = dw.max.y - dw.min.y + 1;
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

void writePng(const Image& img, const std::string& path) {
  double sumLog = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < img.rgb.size(); i += 3) {
    double l = luminance(Rgb(img.rgb[i], img.rgb[i + 1], img.rgb[i + 2]));
    if (l > 0.0) {
      sumLog += std::log(l);
      ++n;
    }
  }
  double exposure = n ? 0.18 / std::exp(sumLog / n) : 1.0;
  std::vector<unsigned char> px(img.rgb.size());
  for (std::size_t i = 0; i < img.rgb.size(); ++i) {
    double v = img.rgb[i] * exposure;
    v = v / (1.0 + v);
    v = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
    px[i] = static_cast<unsigned char>(std::clamp(v * 255.0 + 0.5, 0.0, 255.0));
  }
  writePng8(px, img.width, img.height, path);
}

}  // namespace hr
