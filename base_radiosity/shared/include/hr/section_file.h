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
#include <deque>
#include <functional>
#include <initializer_list>
#include <iosfwd>
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
  SectionWriter(const SectionWriter&) = delete;  // it holds views of its own strings
  SectionWriter& operator=(const SectionWriter&) = delete;
  /// A section whose payload the writer keeps a copy of.
  void add(std::string_view name, std::string payload);
  /// A section whose payload is these pieces one after another, not copied: each must outlive
  /// write() and finish(). For large payloads (a glossy solution's directional data runs to hundreds
  /// of megabytes, and every copy of it was resident at once while the file was written).
  void addPieces(std::string_view name, std::initializer_list<std::string_view> pieces);
  /// A section whose payload is `prefix` then the `size` bytes (producedSize) `produce` writes, never
  /// held whole: produce runs once here (the checksum, for the header) and again in each write(). It
  /// must write the same bytes each time (std::logic_error otherwise) and outlive the writer.
  void addProduced(std::string_view name, std::string prefix, std::function<void(std::ostream&)> produce,
                   std::uint64_t size);
  /// Streams the whole file; the trailer's checksum is computed on the way.
  void write(std::ostream& out) const;
  /// The whole file as one string.
  std::string finish() const;

 private:
  struct Produced {
    std::function<void(std::ostream&)> produce;
    std::uint64_t size = 0;
  };
  std::deque<std::string> owned_;        // headers and copied payloads (a deque: views stay valid)
  std::vector<std::string_view> chunks_;  // the file, in order, trailer excepted; empty views at
                                          // chunk indices listed in produced_
  std::vector<std::pair<std::size_t, Produced>> produced_;
};

/// Bytes that `produce` writes, counted without keeping them.
std::uint64_t producedSize(const std::function<void(std::ostream&)>& produce);

/// Parses and verifies the container: magic, version, every section's bounds and checksum, the
/// trailer. verifyChecksums = false skips the CRCs only (fuzzing reaches the payload parsers that
/// way). Throws InputError naming path and the section.
std::vector<Section> readSections(std::string_view bytes, std::string_view magic, std::uint32_t version,
                                  const std::string& path, bool verifyChecksums = true);

}  // namespace hr
