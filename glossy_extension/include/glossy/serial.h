// Little-endian binary helpers for the distributions' serialization: a tag and a version lead every
// record, so that a foreign or newer stream is rejected with a message instead of misread.
#pragma once
#include <cstdint>
#include <iosfwd>
#include <string>

namespace glossy::serial {

constexpr std::uint32_t kHaarTag = 0x52414148u;   // "HAAR"
constexpr std::uint32_t kTetraTag = 0x41525445u;  // "ETRA"
constexpr std::uint32_t kShTag = 0x48534853u;     // "SHSH"
constexpr std::uint32_t kVersion = 1;

void writeU32(std::ostream& out, std::uint32_t v);
void writeU64(std::ostream& out, std::uint64_t v);
void writeF32(std::ostream& out, float v);
void writeF64(std::ostream& out, double v);
std::uint32_t readU32(std::istream& in);
std::uint64_t readU64(std::istream& in);
float readF32(std::istream& in);
double readF64(std::istream& in);
void writeHeader(std::ostream& out, std::uint32_t tag);
/// Throws std::runtime_error naming `what` unless the stream starts with tag and a known version.
void readHeader(std::istream& in, std::uint32_t tag, const std::string& what);

}  // namespace glossy::serial
