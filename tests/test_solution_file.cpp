// The .ghrs file (format 2, hr/section_file.h): CRC-32 against the standard check value, a round trip
// with an opaque extra section (what an extension adds), a damaged section named in the message, and
// the corruption test: 200 randomly damaged copies of a real solution (bit flips, overwritten runs,
// truncations, insertions, deletions), each given to `glossyhr render`: every one refused with exit 2
// and a message naming the file and the section (or magic, version, trailer), and no image written.
#include <gtest/gtest.h>
#include <hr/section_file.h>
#include <sys/wait.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "helpers.h"
#include "test_dir.h"

namespace fs = std::filesystem;

namespace {

hr::Solution smallSolution() {
  auto s = testutil::solveText(hr::kDefaultSceneJson, testutil::options(1e-2, 2));
  return hr::makeSolution(s.scene, *s.h, s.solver->radiosity());
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(SolutionFile, Crc32MatchesTheStandardCheckValue) {
  EXPECT_EQ(hr::crc32("123456789"), 0xCBF43926u);
  EXPECT_EQ(hr::crc32(""), 0u);
}

TEST(SolutionFile, RoundTripKeepsExtraSections) {
  hr::Solution s = smallSolution();
  hr::setSection(s, "notes", std::string("phong-haar\0\x02\x00\x00\x00opaque", 21));
  s.extension = {"is", 3, std::string("\0binary\xff", 8), {}};
  EXPECT_THROW(hr::setSection(s, "patches", "x"), std::logic_error) << "core names are reserved";
  EXPECT_THROW(hr::setSection(s, "extension", "x"), std::logic_error) << "the extension's section is the core's";
  fs::path p = testutil::testDir() / "s.ghrs";
  hr::saveSolution(s, p.string());
  hr::Solution back = hr::loadSolution(p.string());
  ASSERT_NE(hr::findSection(back, "notes"), nullptr);
  EXPECT_EQ(*hr::findSection(back, "notes"), *hr::findSection(s, "notes"));
  EXPECT_EQ(back.extension.name, "is");
  EXPECT_EQ(back.extension.version, 3u);
  EXPECT_EQ(back.extension.bytes, s.extension.bytes);
  ASSERT_EQ(back.elements.size(), s.elements.size());
  for (std::size_t i = 0; i < s.elements.size(); ++i) ASSERT_EQ(back.elements[i].radiosity, s.elements[i].radiosity);
  EXPECT_EQ(hr::serializeSolution(back), hr::serializeSolution(s)) << "loading and saving again gives the same bytes";
}

/// The extension's bytes written into the file by a producer (as glossyhr solve saves a glossy run,
/// without holding them) give the very file that holding them gives; a producer whose bytes change
/// between its runs is an error, not a file with a wrong header.
TEST(SolutionFile, AProducedExtensionSectionIsTheHeldOnesFile) {
  hr::Solution held = smallSolution();
  std::string payload;
  for (int i = 0; i < 100000; ++i) payload.push_back(char((i * 7919) % 251));
  held.extension = {"is", 3, payload, {}};
  hr::Solution streamed = smallSolution();
  int runs = 0;
  streamed.extension = {"is", 3, {}, [&](std::ostream& o) {
                          ++runs;
                          // In pieces of several sizes, as a serialiser writes.
                          for (std::size_t at = 0; at < payload.size();) {
                            std::size_t n = std::min<std::size_t>(payload.size() - at, 1 + at % 4093);
                            o.write(payload.data() + at, std::streamsize(n));
                            at += n;
                          }
                        }};
  const std::string expected = hr::serializeSolution(held);
  EXPECT_EQ(hr::serializeSolution(streamed), expected);
  EXPECT_GE(runs, 3) << "sized, checksummed, written";
  fs::path p = testutil::testDir() / "streamed.ghrs";
  hr::saveSolution(streamed, p.string());
  EXPECT_EQ(slurp(p), expected);
  EXPECT_EQ(hr::loadSolution(p.string()).extension.bytes, payload);

  // Changed between sizing and checksumming, and only when written.
  hr::Solution changing = smallSolution();
  int calls = 0;
  changing.extension = {"is", 3, {}, [&](std::ostream& o) { o << std::string(std::size_t(10 + calls++), 'x'); }};
  EXPECT_THROW(hr::serializeSolution(changing), std::logic_error);
  hr::Solution late = smallSolution();
  int runs2 = 0;
  late.extension = {"is", 3, {}, [&](std::ostream& o) { o << std::string(runs2++ < 2 ? 10u : 11u, 'x'); }};
  EXPECT_THROW(hr::serializeSolution(late), std::logic_error);
}

TEST(SolutionFile, ADamagedSectionIsNamed) {
  hr::Solution s = smallSolution();
  std::string bytes = hr::serializeSolution(s);
  // The last radiosity value sits just before the trailer: inside "elements".
  bytes[bytes.size() - 8 - 3] ^= 0x10;
  try {
    hr::parseSolution(bytes, "x.ghrs");
    ADD_FAILURE() << "damaged file accepted";
  } catch (const hr::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x.ghrs: section 4 (\"elements\"): checksum mismatch"), std::string::npos) << e.what();
  }
  // Without the checksums the same damage may pass the range checks: the checksum is what catches it.
  std::string negative = hr::serializeSolution(s);
  std::size_t at = negative.size() - 8 - 8;  // last double of the last element's radiosity
  double minusOne = -1.0;
  std::memcpy(negative.data() + at, &minusOne, 8);
  EXPECT_THROW(hr::parseSolution(negative, "x.ghrs", false), hr::InputError) << "negative radiosity refused by range";
}

TEST(SolutionFile, TwoHundredCorruptedFilesAreAllRefused) {
  const fs::path dir = testutil::testDir();
  const fs::path good = dir / "good.ghrs";
  hr::saveSolution(smallSolution(), good.string());
  const std::string bytes = slurp(good);
  std::string text;
  ASSERT_EQ(testutil::runCli("render " + good.string() + " -o " + (dir / "ok.png").string() + " --quiet", text), 0) << text;
  std::mt19937_64 rng(2026);
  auto below = [&](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng); };
  int kinds[5] = {};
  for (int i = 0; i < 200; ++i) {
    std::string bad = bytes;
    const int kind = i % 5;
    ++kinds[kind];
    switch (kind) {
      case 0: bad[below(bad.size())] ^= static_cast<char>(1u << below(8)); break;  // one bit
      case 1: {  // a run of random bytes
        std::size_t at = below(bad.size()), n = 1 + below(32);
        for (std::size_t k = at; k < std::min(bad.size(), at + n); ++k) bad[k] = static_cast<char>(rng());
        if (bad == bytes) bad[at] ^= 1;
        break;
      }
      case 2: bad.resize(below(bad.size())); break;  // truncated
      case 3: bad.insert(below(bad.size()), std::string(1 + below(16), static_cast<char>(rng()))); break;
      default: bad.erase(below(bad.size()), 1 + below(16)); break;
    }
    ASSERT_NE(bad, bytes);
    const fs::path f = dir / ("bad" + std::to_string(i) + ".ghrs"), img = dir / ("bad" + std::to_string(i) + ".png");
    std::ofstream(f, std::ios::binary) << bad;
    int status = testutil::runCli("render " + f.string() + " -o " + img.string() + " --quiet", text);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2) << "corruption " << i << " (kind " << kind << "): " << text;
    EXPECT_NE(text.find(f.string()), std::string::npos) << text;
    bool named = text.find("section") != std::string::npos || text.find("trailer") != std::string::npos ||
                 text.find("magic") != std::string::npos || text.find("version") != std::string::npos;
    EXPECT_TRUE(named) << "corruption " << i << ": " << text;
    EXPECT_FALSE(fs::exists(img)) << "corruption " << i << " rendered";
    fs::remove(f);
  }
  std::printf("corruption test: 200 files (%d bit flips, %d overwritten runs, %d truncations, %d insertions, %d deletions), all refused\n",
              kinds[0], kinds[1], kinds[2], kinds[3], kinds[4]);
}

}  // namespace
