// The tagged-section container (see hr/section_file.h).
#include <array>
#include <cstring>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <hr/echo.h>
#include <hr/section_file.h>
#include <hr/types.h>

namespace hr {
namespace {

constexpr std::size_t kMaxName = 64;

const std::array<std::uint32_t, 256>& crcTable() {
  static const std::array<std::uint32_t, 256> t = [] {
    std::array<std::uint32_t, 256> r{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      r[i] = c;
    }
    return r;
  }();
  return t;
}

template <class T>
void put(std::string& b, T v) {
  char raw[sizeof(T)];
  std::memcpy(raw, &v, sizeof(T));  // the project targets little-endian machines (x86-64, arm64)
  b.append(raw, sizeof(T));
}

template <class T>
T get(std::string_view b, std::size_t at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof(T));
  return v;
}

/// Counts the bytes written through it and carries a CRC-32 over them; forwards them to `next` when
/// given. Unbuffered: the serialisers write in pieces of a few bytes to a few kilobytes.
class CrcBuffer : public std::streambuf {
 public:
  explicit CrcBuffer(std::streambuf* next = nullptr, std::uint32_t crc = 0, bool checksum = true)
      : next_(next), crc_(crc), checksum_(checksum) {}
  std::uint64_t count() const { return n_; }
  std::uint32_t crc() const { return crc_; }
  bool failed() const { return failed_; }

 protected:
  std::streamsize xsputn(const char* p, std::streamsize n) override {
    if (checksum_) crc_ = crc32(std::string_view(p, std::size_t(n)), crc_);
    n_ += std::uint64_t(n);
    if (next_ && next_->sputn(p, n) != n) failed_ = true;
    return n;
  }
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return c;
    char ch = traits_type::to_char_type(c);
    xsputn(&ch, 1);
    return c;
  }

 private:
  std::streambuf* next_;
  std::uint32_t crc_;
  bool checksum_;
  std::uint64_t n_ = 0;
  bool failed_ = false;
};

}  // namespace

std::uint64_t producedSize(const std::function<void(std::ostream&)>& produce) {
  CrcBuffer b(nullptr, 0, false);
  std::ostream o(&b);
  produce(o);
  return b.count();
}

std::uint32_t crc32(std::string_view bytes, std::uint32_t crc) {
  const auto& t = crcTable();
  crc = ~crc;
  for (char ch : bytes) crc = t[(crc ^ static_cast<unsigned char>(ch)) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

SectionWriter::SectionWriter(std::string_view magic, std::uint32_t version) {
  std::string head(magic);
  put(head, version);
  chunks_.push_back(owned_.emplace_back(std::move(head)));
}

void SectionWriter::add(std::string_view name, std::string payload) {
  const std::string& kept = owned_.emplace_back(std::move(payload));
  addPieces(name, {kept});
}

void SectionWriter::addPieces(std::string_view name, std::initializer_list<std::string_view> pieces) {
  if (name.empty() || name.size() > kMaxName) throw std::logic_error("section name must have 1-64 bytes");
  std::uint64_t size = 0;
  for (std::string_view p : pieces) size += p.size();
  std::string head;
  put(head, static_cast<std::uint32_t>(name.size()));
  head.append(name);
  put(head, size);
  std::uint32_t crc = crc32(head);
  for (std::string_view p : pieces) crc = crc32(p, crc);
  put(head, crc);
  chunks_.push_back(owned_.emplace_back(std::move(head)));
  for (std::string_view p : pieces) chunks_.push_back(p);
}

void SectionWriter::addProduced(std::string_view name, std::string prefix, std::function<void(std::ostream&)> produce,
                                std::uint64_t size) {
  if (name.empty() || name.size() > kMaxName) throw std::logic_error("section name must have 1-64 bytes");
  Produced p{std::move(produce), size};
  std::string head;
  put(head, static_cast<std::uint32_t>(name.size()));
  head.append(name);
  put(head, static_cast<std::uint64_t>(prefix.size() + p.size));
  // The section's CRC runs over the header, the prefix and the produced bytes, in that order.
  CrcBuffer c(nullptr, crc32(prefix, crc32(head)));
  std::ostream oc(&c);
  p.produce(oc);
  if (c.count() != p.size) throw std::logic_error("a produced section wrote different sizes on two runs");
  put(head, c.crc());
  chunks_.push_back(owned_.emplace_back(std::move(head)));
  chunks_.push_back(owned_.emplace_back(std::move(prefix)));
  produced_.emplace_back(chunks_.size(), std::move(p));
  chunks_.emplace_back();
}

void SectionWriter::write(std::ostream& out) const {
  std::uint32_t crc = 0;
  auto next = produced_.begin();
  for (std::size_t i = 0; i < chunks_.size(); ++i) {
    if (next != produced_.end() && next->first == i) {
      CrcBuffer through(out.rdbuf(), crc);
      std::ostream o(&through);
      next->second.produce(o);
      if (through.failed()) out.setstate(std::ios::badbit);
      // Checked against the first run by its size: a section whose size changed would carry a wrong
      // header (and the section's CRC catches changed bytes when the file is read).
      if (through.count() != next->second.size)
        throw std::logic_error("a produced section was sized at " + std::to_string(next->second.size) +
                               " bytes and wrote " + std::to_string(through.count()));
      crc = through.crc();
      ++next;
      continue;
    }
    std::string_view c = chunks_[i];
    out.write(c.data(), static_cast<std::streamsize>(c.size()));
    crc = crc32(c, crc);
  }
  std::string trailer = "END!";
  put(trailer, crc);
  out.write(trailer.data(), static_cast<std::streamsize>(trailer.size()));
}

std::string SectionWriter::finish() const {
  std::ostringstream out;
  write(out);
  return std::move(out).str();
}

std::vector<Section> readSections(std::string_view b, std::string_view magic, std::uint32_t version,
                                  const std::string& path, bool verify) {
  if (b.size() < magic.size() + 4 || b.substr(0, magic.size()) != magic)
    throw InputError(path + ": not a glossyhr solution file (bad magic)");
  std::uint32_t v = get<std::uint32_t>(b, magic.size());
  if (v != version)
    throw InputError(path + ": file format version " + std::to_string(v) + " is not supported (expected " +
                     std::to_string(version) + "; a damaged file reads as a wrong version too)");
  std::vector<Section> out;
  std::size_t at = magic.size() + 4;
  for (std::size_t index = 0;; ++index) {
    const std::string which = "section " + std::to_string(index);
    if (b.size() - at == 8 && b.substr(at, 4) == "END!") {
      if (verify && get<std::uint32_t>(b, at + 4) != crc32(b.substr(0, at)))
        throw InputError(path + ": trailer: checksum mismatch (the file is damaged)");
      return out;
    }
    if (b.size() - at < 4 + 8 + 4) throw InputError(path + ": " + which + ": truncated file (no trailer)");
    std::uint32_t nameLen = get<std::uint32_t>(b, at);
    if (nameLen == 0 || nameLen > kMaxName || b.size() - at - 4 < std::size_t(nameLen) + 12)
      throw InputError(path + ": " + which + ": bad section header (name length " + std::to_string(nameLen) + ")");
    std::string name(b.substr(at + 4, nameLen));
    const std::string label = which + " (" + echo(name) + ")";
    std::uint64_t len = get<std::uint64_t>(b, at + 4 + nameLen);
    std::uint32_t crc = get<std::uint32_t>(b, at + 4 + nameLen + 8);
    std::size_t body = at + 4 + nameLen + 12;
    if (len > b.size() - body) throw InputError(path + ": " + label + ": truncated file (section runs past the end)");
    std::string_view payload = b.substr(body, std::size_t(len));
    if (verify && crc32(payload, crc32(b.substr(at, 4 + nameLen + 8))) != crc)
      throw InputError(path + ": " + label + ": checksum mismatch (the file is damaged)");
    out.push_back({std::move(name), std::string(payload)});
    at = body + std::size_t(len);
  }
}

}  // namespace hr
