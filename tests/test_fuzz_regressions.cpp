// Replays every fuzzing regression input (tests/fuzz_regressions/<target>/, the inputs libFuzzer once
// crashed on) and every fuzzing seed through the same entry points the fuzz targets use: each must be
// accepted or refused with an InputError, never crash or throw anything else. Runs in the normal
// suite, so the ASan + UBSan build replays them too.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "fuzz_entries.h"

namespace fs = std::filesystem;

namespace {

std::size_t replay(const std::string& target, const fs::path& folder) {
  ghrfuzz::Entry f = ghrfuzz::entry(target);
  EXPECT_NE(f, nullptr) << target;
  std::size_t n = 0;
  if (!f || !fs::is_directory(folder)) return 0;
  for (const auto& e : fs::directory_iterator(folder)) {
    if (!e.is_regular_file() || e.path().filename() == "README.md") continue;
    std::ifstream in(e.path(), std::ios::binary);
    std::string bytes(std::istreambuf_iterator<char>(in), {});
    SCOPED_TRACE(e.path().string());
    EXPECT_NO_THROW(f(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
    ++n;
  }
  return n;
}

TEST(FuzzRegressions, EveryRegressionInputAndSeedIsHandled) {
  const fs::path src(GHR_SOURCE_DIR);
  const std::pair<const char*, fs::path> seeds[] = {{"scene_json", src / "scenes"},      {"mgf", src / "scenes/mgf"},
                                                    {"obj", src / "fuzz/seeds/obj"},     {"ply", src / "fuzz/seeds/ply"},
                                                    {"solution", src / "fuzz/seeds/solution"}};
  for (const auto& [target, folder] : seeds) {
    EXPECT_GT(replay(target, folder), 0u) << "no seed for " << target;
    replay(target, src / "tests/fuzz_regressions" / target);
  }
}

}  // namespace
