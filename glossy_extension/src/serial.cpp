// Byte-order-explicit reading and writing of the distributions' binary records.
#include <glossy/serial.h>

#include <cstring>
#include <istream>
#include <ostream>
#include <stdexcept>

namespace glossy::serial {
namespace {

template <class T>
void put(std::ostream& out, T v) {
  unsigned char b[sizeof(T)];
  for (std::size_t i = 0; i < sizeof(T); ++i) b[i] = static_cast<unsigned char>((v >> (8 * i)) & 0xFF);
  out.write(reinterpret_cast<const char*>(b), sizeof b);
}

template <class T>
T get(std::istream& in) {
  unsigned char b[sizeof(T)];
  if (!in.read(reinterpret_cast<char*>(b), sizeof b)) throw std::runtime_error("distribution stream: truncated");
  T v = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) v |= static_cast<T>(b[i]) << (8 * i);
  return v;
}

}  // namespace

void writeU32(std::ostream& out, std::uint32_t v) { put(out, v); }
void writeU64(std::ostream& out, std::uint64_t v) { put(out, v); }
void writeF32(std::ostream& out, float v) {
  std::uint32_t u;
  std::memcpy(&u, &v, sizeof u);
  put(out, u);
}
void writeF64(std::ostream& out, double v) {
  std::uint64_t u;
  std::memcpy(&u, &v, sizeof u);
  put(out, u);
}
std::uint32_t readU32(std::istream& in) { return get<std::uint32_t>(in); }
std::uint64_t readU64(std::istream& in) { return get<std::uint64_t>(in); }
float readF32(std::istream& in) {
  std::uint32_t u = get<std::uint32_t>(in);
  float v;
  std::memcpy(&v, &u, sizeof v);
  return v;
}

double readF64(std::istream& in) {
  std::uint64_t u = get<std::uint64_t>(in);
  double v;
  std::memcpy(&v, &u, sizeof v);
  return v;
}

void writeHeader(std::ostream& out, std::uint32_t tag) {
  writeU32(out, tag);
  writeU32(out, kVersion);
}

void readHeader(std::istream& in, std::uint32_t tag, const std::string& what) {
  std::uint32_t t = readU32(in);
  if (t != tag) throw std::runtime_error(what + ": not a " + what + " record");
  std::uint32_t v = readU32(in);
  if (v != kVersion) throw std::runtime_error(what + ": unsupported version " + std::to_string(v));
}

}  // namespace glossy::serial
