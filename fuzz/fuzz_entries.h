// The fuzzed entry points: each takes arbitrary bytes, runs one reader the way the command line does,
// and must either succeed or throw hr::InputError; anything else (a crash, a sanitizer report, a
// hang, another exception) is a finding. Shared by the libFuzzer targets (fuzz_target.cpp) and by the
// test suite, which replays every regression input in tests/fuzz_regressions/ through them.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace ghrfuzz {

int sceneJson(const std::uint8_t* data, std::size_t size);
int mgf(const std::uint8_t* data, std::size_t size);
int obj(const std::uint8_t* data, std::size_t size);
int ply(const std::uint8_t* data, std::size_t size);
int solution(const std::uint8_t* data, std::size_t size);

/// The entry point by target name ("scene_json", "mgf", "obj", "ply", "solution"), or nullptr.
using Entry = int (*)(const std::uint8_t*, std::size_t);
Entry entry(const std::string& target);

}  // namespace ghrfuzz
