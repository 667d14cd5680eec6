// The extension's section of the solution file: a saved solution loads over a view of its elements
// (no clusters) and evaluates bit for bit as before; any damage (bit flips, truncation, random bytes,
// overwritten spans, trailing bytes) is refused with hr::InputError and leaves the loaded state as it
// was; a section of another version or one that does not fit the solution's elements is refused with
// a message that says so.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include <cstdio>
#include <random>

#include "directions.h"
#include "fake_host.h"
#include "../saved_bytes.h"

namespace {

using glossy::Rgb;
using glossy::Vec3;
using glossy::kPi;
using testhost::NodeId;

/// A lit scene whose extension has reflected and pulled once.
struct Solved {
  testhost::Scene scene;
  std::unique_ptr<glossy::IlluminationSamples> ext;
  /// shooting: each leaf's samples arrive in two passes (reflectShot), whose shown lights are joined.
  explicit Solved(const char* basis, bool shooting = false) : ext(testhost::configured({{"basis", basis}})) {
    ext->attach(scene.host);
    std::mt19937_64 g(31);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (NodeId leaf : scene.host.simulatedLeaves(*ext)) {
      Vec3 n = scene.host.info(leaf).normal;
      std::vector<hr::IncidentSample> s;
      for (int k = 0; k < 4; ++k) {
        s.push_back(testhost::sample(testhost::around(n, std::acos(u(g)), 2 * kPi * u(g)), Rgb(u(g), 1.0, u(g))));
        // A flat sender 2 m off facing the leaf askew, half of them 50 x 20 cm rectangles: the shown
        // light keeps its distance, normal and shape.
        s.back().distance = 2.0, s.back().radius = k % 2 ? 0.2 : 0.01;
        const Vec3 sn = -glm::normalize(s.back().toSender + 0.3 * testhost::around(n, 1.2, k));
        s.back().senderNormal = glm::vec3(sn);
        if (k % 2) s.back().senderShape = {glm::vec3(0.25 * hr::rectangleSide(glm::vec3(n), sn)), 0.1f};
      }
      // And a lamp in 10 x 10 pieces, each under the shown share: joined, its pieces kept as deposited.
      const Vec3 wi = testhost::around(n, 0.6, 2.0);
      Vec3 a, b;
      glossy::orthonormalBasis(wi, a, b);
      for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j) {
          const Vec3 to = glm::normalize(2.0 * wi + 0.01 * ((i - 4.5) * a + (j - 4.5) * b));
          s.push_back(testhost::sample(to, Rgb(0.01)));
          s.back().distance = 2.0, s.back().radius = 0.006, s.back().senderNormal = glm::vec3(-wi);
        }
      if (!shooting) {
        ext->reflect(leaf, s);
        continue;
      }
      // The point sources in the second pass: samples of their own beside pieces joined before.
      std::rotate(s.begin(), s.begin() + 4, s.end());
      const auto half = s.begin() + std::ptrdiff_t(s.size() / 2);
      ext->reflectShot(leaf, std::vector<hr::IncidentSample>(s.begin(), half));
      ext->reflectShot(leaf, std::vector<hr::IncidentSample>(half, s.end()));
    }
    scene.host.pullAll(*ext);
  }
};

/// Everything display and the energy audit read of the leaves, for bitwise comparison.
std::vector<double> fingerprint(const hr::Extension& ext, const testhost::FakeHost& host) {
  std::vector<double> out;
  std::mt19937_64 g(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (NodeId leaf : host.simulatedLeaves(ext)) {
    auto push = [&](const Rgb& v) { out.insert(out.end(), {v.x, v.y, v.z}); };
    push(ext.reflectedPower(leaf));
    out.push_back(double(ext.coefficients(leaf)));
    for (int k = 0; k < 500; ++k) {
      Vec3 d = testdirs::sphere(g), s;
      push(ext.intensity(leaf, d));
      push(ext.radiance(leaf, d));
      push(ext.radiance(leaf, d, Vec3(0.0), host.info(leaf).center));  // with the shown light (shown_light.h)
      push(ext.radiance(leaf, d, Vec3(0.0), host.info(leaf).center + 0.3 * testdirs::sphere(g)));  // re-aimed there
      push(ext.intensityBound(leaf, d, 0.9));
      push(ext.sampleExitant(leaf, u(g), u(g), s));
      push(s);
    }
  }
  return out;
}

TEST(IsFile, RoundTripEvaluatesBitIdentically) {
  for (const char* basis : {"haar", "tetra", "sh"}) {
    Solved s(basis);
    std::string bytes = testutil::savedBytes(*s.ext);
    testhost::FakeHost saved = s.scene.host.elementsOnly();
    glossy::IlluminationSamples loaded;  // default options: the section states its basis
    loaded.load(bytes, saved);
    EXPECT_EQ(loaded.basis().basis, s.ext->basis().basis) << basis;
    EXPECT_EQ(fingerprint(loaded, saved), fingerprint(*s.ext, s.scene.host)) << basis;
    EXPECT_EQ(testutil::savedBytes(loaded), bytes) << basis << ": saving again gives the same bytes";
    std::printf("%-5s section: %zu bytes for %zu glossy leaves\n", basis, bytes.size(), saved.simulatedLeaves(loaded).size());
  }
  // A shooting solution's leaves: two passes' shown lights joined, a lamp's pieces from both.
  Solved s("haar", true);
  const std::string bytes = testutil::savedBytes(*s.ext);
  testhost::FakeHost saved = s.scene.host.elementsOnly();
  glossy::IlluminationSamples loaded;
  loaded.load(bytes, saved);
  EXPECT_EQ(fingerprint(loaded, saved), fingerprint(*s.ext, s.scene.host)) << "shooting";
  EXPECT_EQ(testutil::savedBytes(loaded), bytes) << "shooting: saving again gives the same bytes";
  std::size_t pieces = 0;  // the round trip carried joined pieces
  for (NodeId leaf : saved.simulatedLeaves(loaded))
    if (const auto* l = loaded.light(leaf); l && l->shown) pieces += l->shown->deposited.size();
  EXPECT_GT(pieces, 0u);
}

TEST(IsFile, DamagedSectionsAreRefused) {
  // 200 damaged copies per basis: bit flips, truncations, random bytes, overwritten spans, trailing
  // bytes. Each refused with InputError; after all of them the loaded solution is unchanged.
  for (const char* basis : {"haar", "tetra", "sh"}) {
    Solved s(basis);
    const std::string bytes = testutil::savedBytes(*s.ext);
    testhost::FakeHost saved = s.scene.host.elementsOnly();
    glossy::IlluminationSamples ext;
    ext.load(bytes, saved);
    const auto before = fingerprint(ext, saved);
    std::mt19937_64 g(2024);
    auto below = [&](std::size_t n) { return std::size_t(g() % std::max<std::size_t>(n, 1)); };
    int refused = 0;
    for (int k = 0; k < 200; ++k) {
      std::string bad = bytes;
      switch (k % 5) {
        case 0:  // one to three bit flips
          for (std::size_t f = 0, n = 1 + below(3); f < n; ++f) bad[below(bad.size())] ^= char(1 << below(8));
          break;
        case 1: bad.resize(below(bad.size())); break;
        case 2: {
          bad.resize(below(2 * bytes.size()));
          for (char& c : bad) c = char(g());
          break;
        }
        case 3: {
          std::size_t at = below(bad.size()), len = 1 + below(64);
          for (std::size_t i = at; i < std::min(bad.size(), at + len); ++i) bad[i] = char(g());
          if (bad == bytes) bad[at] ^= 1;
          break;
        }
        default: bad += std::string(1 + below(16), char(g())); break;
      }
      try {
        ext.load(bad, saved);
        ADD_FAILURE() << basis << ": damaged copy " << k << " accepted";
      } catch (const hr::InputError& e) {
        ++refused;
        EXPECT_NE(std::string(e.what()).find("section of extension 'is'"), std::string::npos) << e.what();
      }
    }
    EXPECT_EQ(refused, 200) << basis;
    EXPECT_EQ(fingerprint(ext, saved), before) << basis << ": a refused load changes nothing";
  }
}

/// FNV-1a 64 as the section uses it, to forge well-checksummed sections.
std::string resealed(std::string body) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : body) h = (h ^ c) * 0x100000001b3ull;
  for (int i = 0; i < 8; ++i) body += char((h >> (8 * i)) & 0xFF);
  return body;
}

void expectRefusal(glossy::IlluminationSamples& ext, const std::string& bytes, const hr::HostView& view, const std::string& needle) {
  try {
    ext.load(bytes, view);
    ADD_FAILURE() << "accepted; expected: " << needle;
  } catch (const hr::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(IsFile, ForeignOrMismatchedSectionsAreRefusedWithAClearMessage) {
  Solved s("haar");
  const std::string bytes = testutil::savedBytes(*s.ext);
  std::string body = bytes.substr(0, bytes.size() - 8);
  testhost::FakeHost saved = s.scene.host.elementsOnly();
  glossy::IlluminationSamples ext;
  expectRefusal(ext, "", saved, "truncated");
  expectRefusal(ext, bytes.substr(0, bytes.size() - 1), saved, "checksum mismatch");
  std::string v7 = body;
  v7[4] = 7;  // the format version field
  expectRefusal(ext, resealed(v7), saved, "format version 7, this build reads version 6");
  // The shown light (last in the section): its last sample ends with its sender's normal, distance,
  // radius, shape's half-axis and half-width. The radius made negative, the normal twice a unit, the
  // half-width negative, and the half-axis along the normal (out of the sender's plane).
  std::string radius = body;
  const double minusOne = -1.0, two = 2.0;
  std::memcpy(&radius[radius.size() - 40], &minusOne, 8);
  expectRefusal(ext, resealed(radius), saved, "shown light: sample");
  std::string normal = body;
  for (int c = 0; c < 3; ++c) {
    double v;
    std::memcpy(&v, &normal[normal.size() - 72 + 8 * c], 8);
    v *= two;
    std::memcpy(&normal[normal.size() - 72 + 8 * c], &v, 8);
  }
  expectRefusal(ext, resealed(normal), saved, "shown light: sample");
  // The last sample's piece count (before its 168 bytes of fields) past the pieces there are.
  std::string pieces = body;
  const std::uint32_t many = 1000;
  std::memcpy(&pieces[pieces.size() - 172], &many, 4);
  expectRefusal(ext, resealed(pieces), saved, "names pieces beyond the");
  std::string first = body;  // its first piece past them
  std::memcpy(&first[first.size() - 176], &many, 4);
  expectRefusal(ext, resealed(first), saved, "names pieces beyond the");
  std::string width = body;
  std::memcpy(&width[width.size() - 8], &minusOne, 8);
  expectRefusal(ext, resealed(width), saved, "shown light: sample");
  std::string axis = body;
  std::memcpy(&axis[axis.size() - 32], &axis[axis.size() - 72], 24);
  expectRefusal(ext, resealed(axis), saved, "shown light: sample");
  std::string flag = body;
  flag[8] = 2;  // the automatic-basis flag: 0 or 1
  expectRefusal(ext, resealed(flag), saved, "bad automatic-basis flag 2");
  std::string tag = body;
  tag[52] = 2;  // the first record's basis (after the 48-byte header and its element index)
  expectRefusal(ext, resealed(tag), saved, "a sh record in a haar section");
  std::string magic = body;
  magic[0] = 'X';
  expectRefusal(ext, resealed(magic), saved, "not an Illumination Samples section");
  std::string eps = body;
  for (int i = 16; i < 24; ++i) eps[std::size_t(i)] = char(0xFF);  // dir-eps: a NaN
  expectRefusal(ext, resealed(eps), saved, "bad dir-eps");
  // Views the section does not fit.
  testhost::FakeHost fewer = saved;
  fewer.elements.resize(3);
  expectRefusal(ext, bytes, fewer, "more distributions than the solution has elements");
  testhost::FakeHost matte = saved;
  matte.materials[0].specular = Rgb(0.0);
  expectRefusal(ext, bytes, matte, "its material is not glossy");
  testhost::FakeHost split = saved;
  split.split(s.scene.wall);
  expectRefusal(ext, bytes, split, "not a planar leaf of the solution");
}

}  // namespace
