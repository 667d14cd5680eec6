// One libFuzzer target; GHR_FUZZ_ENTRY (set per target in CMakeLists.txt) names its entry point.
#include "fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ghrfuzz::GHR_FUZZ_ENTRY(data, size);
}
