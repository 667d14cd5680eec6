// A binary container of tagged sections, each with its length and a CRC-32, for files that travel
// between machines (the .ghrs solution). Layout, little-endian:
//   magic (8 bytes) | u32 version
//   per section: u32 name length (1-64) | name | u64 payload length | u32 CRC-32 | payload
//     (the CRC-32 covers the name length, the name, the payload length and the payload)
//   trailer: "END!" | u32 CRC-32 of every byte before the trailer
// CRC-32 is the IEEE polynomial (0xEDB88320, reflected, initial and final xor 0xFFFFFFFF: zlib's).
// A damaged file is refused with a message naming the section; a new section is one more add().
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hr {

std::uint32_t crc32(std::string_view bytes, std::uint32_t crc = 0);

struct Section {
  std::string name;
  std::string payload;
};

class SectionWriter {
 public:
  SectionWriter(std::string_view magic, std::uint32_t version);
  void add(std::string_view name, std::string_view payload);
  /// The whole file.
  std::string finish() const;

 private:
  std::string buf_;
};

/// Parses and verifies the container: magic, version, every section's bounds and checksum, the
/// trailer. verifyChecksums = false skips the CRCs only (fuzzing reaches the payload parsers that
/// way). Throws InputError naming path and the section.
std::vector<Section> readSections(std::string_view bytes, std::string_view magic, std::uint32_t version,
                                  const std::string& path, bool verifyChecksums = true);

}  // namespace hr
