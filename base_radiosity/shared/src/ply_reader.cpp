// PLY parsing (see ply_reader.h).
#include "ply_reader.h"

#include <hr/echo.h>
#include <hr/limits.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <sstream>

namespace hr {
namespace {

enum class Format { Ascii, LittleEndian, BigEndian };

struct Property {
  std::string name;
  int size = 0;        // bytes of the value (binary), 0 when not a known type
  bool isFloat = false, isSigned = false;
  bool list = false;
  int countSize = 0;   // list: bytes of the count
  bool countSigned = false;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
};

/// Size and kind of a PLY scalar type name; false for an unknown name.
bool scalarType(const std::string& t, int& size, bool& isFloat, bool& isSigned) {
  static const struct {
    const char* name;
    int size;
    bool isFloat, isSigned;
  } kTypes[] = {{"char", 1, false, true},    {"int8", 1, false, true},     {"uchar", 1, false, false},
                {"uint8", 1, false, false},  {"short", 2, false, true},    {"int16", 2, false, true},
                {"ushort", 2, false, false}, {"uint16", 2, false, false},  {"int", 4, false, true},
                {"int32", 4, false, true},   {"uint", 4, false, false},    {"uint32", 4, false, false},
                {"float", 4, true, true},    {"float32", 4, true, true},   {"double", 8, true, true},
                {"float64", 8, true, true}};
  for (const auto& k : kTypes)
    if (t == k.name) {
      size = k.size, isFloat = k.isFloat, isSigned = k.isSigned;
      return true;
    }
  return false;
}

class Body {
 public:
  Body(const std::string& bytes, std::size_t pos, Format f, const std::string& path)
      : b_(bytes), pos_(pos), f_(f), path_(path) {}

  double value(int size, bool isFloat, bool isSigned, const std::string& what) {
    if (f_ == Format::Ascii) return token(what);
    if (pos_ + std::size_t(size) > b_.size()) fail(what, "file ends inside the data");
    unsigned char raw[8];
    std::memcpy(raw, b_.data() + pos_, std::size_t(size));
    pos_ += std::size_t(size);
    if (f_ == Format::BigEndian) std::reverse(raw, raw + size);
    if (isFloat) {
      if (size == 4) {
        float v;
        std::memcpy(&v, raw, 4);
        return v;
      }
      double v;
      std::memcpy(&v, raw, 8);
      return v;
    }
    std::uint64_t u = 0;
    for (int i = size - 1; i >= 0; --i) u = (u << 8) | raw[i];
    if (isSigned && size < 8 && (u >> (8 * size - 1)) & 1u) return double(std::int64_t(u) - (std::int64_t(1) << (8 * size)));
    return double(u);
  }
  [[noreturn]] void fail(const std::string& what, const std::string& msg) const {
    std::string where = f_ == Format::Ascii ? "line " + std::to_string(1 + std::count(b_.begin(), b_.begin() + std::ptrdiff_t(std::min(pos_, b_.size())), '\n'))
                                            : "byte " + std::to_string(pos_);
    throw InputError(path_ + ": " + where + ": " + what + ": " + msg);
  }

 private:
  double token(const std::string& what) {
    while (pos_ < b_.size() && std::isspace(static_cast<unsigned char>(b_[pos_]))) ++pos_;
    std::size_t start = pos_;
    while (pos_ < b_.size() && !std::isspace(static_cast<unsigned char>(b_[pos_]))) ++pos_;
    if (start == pos_) fail(what, "file ends inside the data");
    std::string t = b_.substr(start, std::min<std::size_t>(pos_ - start, 64));
    char* end = nullptr;
    double v = std::strtod(t.c_str(), &end);
    if (pos_ - start > 64 || end != t.c_str() + t.size()) fail(what, "not a number: " + echo(b_.substr(start, pos_ - start)));
    return v;
  }

  const std::string& b_;
  std::size_t pos_;
  Format f_;
  const std::string& path_;
};

}  // namespace

MeshData parsePly(const std::string& bytes, const std::string& path) {
  // ---- header -----------------------------------------------------------------------------------
  constexpr std::size_t kMaxHeader = 64 * 1024;
  std::size_t end = std::string::npos;
  for (std::size_t at = bytes.find("end_header"); at != std::string::npos && at < kMaxHeader; at = bytes.find("end_header", at + 1))
    if (at > 0 && bytes[at - 1] == '\n') {
      end = at;
      break;
    }
  if (bytes.compare(0, 3, "ply") != 0) throw InputError(path + ": line 1: not a PLY file (no \"ply\" magic)");
  if (end == std::string::npos) throw InputError(path + ": PLY header has no end_header line within its first 64 KiB");
  std::size_t body = bytes.find('\n', end);
  body = body == std::string::npos ? bytes.size() : body + 1;
  std::istringstream header(bytes.substr(0, end));
  std::vector<Element> elements;
  bool haveFormat = false;
  Format format = Format::Ascii;
  std::string line;
  for (std::size_t no = 1; std::getline(header, line); ++no) {
    std::istringstream ls(line);
    std::vector<std::string> t;
    for (std::string w; ls >> w;) t.push_back(w);
    auto fail = [&](const std::string& msg) -> void {
      throw InputError(path + ": line " + std::to_string(no) + ": " + msg);
    };
    if (no == 1) {
      if (t.size() != 1 || t[0] != "ply") fail("not a PLY file (no \"ply\" magic)");
      continue;
    }
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "format") {
      if (t.size() != 3 || t[2] != "1.0") fail("expected: format ascii|binary_little_endian|binary_big_endian 1.0");
      if (t[1] == "ascii") format = Format::Ascii;
      else if (t[1] == "binary_little_endian") format = Format::LittleEndian;
      else if (t[1] == "binary_big_endian") format = Format::BigEndian;
      else fail("unknown format " + echo(t[1]));
      haveFormat = true;
    } else if (t[0] == "element") {
      if (t.size() != 3) fail("expected: element NAME COUNT");
      char* e = nullptr;
      errno = 0;
      unsigned long long n = std::strtoull(t[2].c_str(), &e, 10);
      if (t[2][0] == '-' || e != t[2].c_str() + t[2].size() || errno != 0) fail("element count " + echo(t[2]) + " is not a count");
      elements.push_back({t[1], n, {}});
    } else if (t[0] == "property") {
      if (elements.empty()) fail("property before any element");
      Property p;
      bool ok;
      if (t.size() == 5 && t[1] == "list") {
        int cs = 0;
        bool cf = false, csg = false;
        ok = scalarType(t[2], cs, cf, csg) && !cf && scalarType(t[3], p.size, p.isFloat, p.isSigned);
        p.list = true, p.countSize = cs, p.countSigned = csg, p.name = t[4];
      } else {
        ok = t.size() == 3 && scalarType(t[1], p.size, p.isFloat, p.isSigned);
        p.name = t.size() == 3 ? t[2] : "";
      }
      if (!ok) fail("expected: property TYPE NAME or property list COUNT_TYPE TYPE NAME (integer count)");
      elements.back().props.push_back(p);
    } else {
      fail("unknown header keyword " + echo(t[0]));
    }
  }
  if (!haveFormat) throw InputError(path + ": PLY header has no format line");
  // Every declared element must fit in the bytes that follow: a header that claims 4e9 vertices in a
  // small file is refused before anything is allocated.
  const std::uint64_t avail = bytes.size() - body;
  long double need = 0;
  for (const Element& el : elements) {
    std::uint64_t each = 0;
    for (const Property& p : el.props) each += format == Format::Ascii ? 2 : std::uint64_t(p.list ? p.countSize : p.size);
    if (el.count > 0 && el.props.empty()) throw InputError(path + ": element " + echo(el.name) + " has no properties");
    need += (long double)el.count * each;
    if (el.count > limits::kMaxMeshElements)
      throw InputError(path + ": element " + echo(el.name) + " declares " + std::to_string(el.count) +
                       ", more than the limit of " + std::to_string(limits::kMaxMeshElements));
  }
  if (need > (long double)avail)
    throw InputError(path + ": the header declares more data than the file holds (" + std::to_string(avail) +
                     " bytes after the header)");

  // ---- body -------------------------------------------------------------------------------------
  Body in(bytes, body, format, path);
  std::vector<Vec3> vertices;
  std::vector<std::vector<std::uint64_t>> faces;
  for (const Element& el : elements) {
    const bool isVertex = el.name == "vertex", isFace = el.name == "face";
    int xi = -1, yi = -1, zi = -1, fi = -1;
    for (std::size_t k = 0; k < el.props.size(); ++k) {
      const Property& p = el.props[k];
      if (isVertex && !p.list && p.name == "x") xi = int(k);
      if (isVertex && !p.list && p.name == "y") yi = int(k);
      if (isVertex && !p.list && p.name == "z") zi = int(k);
      if (isFace && p.list && (p.name == "vertex_indices" || p.name == "vertex_index")) fi = int(k);
    }
    if (isVertex && (xi < 0 || yi < 0 || zi < 0)) throw InputError(path + ": element vertex lacks an x, y or z property");
    if (isFace && fi < 0) throw InputError(path + ": element face lacks a vertex_indices list");
    for (std::uint64_t i = 0; i < el.count; ++i) {
      const std::string what = el.name.substr(0, 32) + " " + std::to_string(i);
      Vec3 v(0.0);
      for (std::size_t k = 0; k < el.props.size(); ++k) {
        const Property& p = el.props[k];
        if (!p.list) {
          double x = in.value(p.size, p.isFloat, p.isSigned, what);
          if (int(k) == xi) v.x = x;
          if (int(k) == yi) v.y = x;
          if (int(k) == zi) v.z = x;
          continue;
        }
        double n = in.value(p.countSize, false, p.countSigned, what);
        if (!(n >= 0 && n <= double(limits::kMaxFaceVertices)))
          in.fail(what, "list length " + std::to_string(n) + " outside [0, " + std::to_string(limits::kMaxFaceVertices) + "]");
        std::vector<std::uint64_t> idx;
        for (int j = 0; j < int(n); ++j) {
          double x = in.value(p.size, p.isFloat, p.isSigned, what);
          if (int(k) == fi) {
            if (!(x >= 0 && x < 4294967295.0 && x == std::floor(x))) in.fail(what, "vertex index " + std::to_string(x) + " is not an index");
            idx.push_back(std::uint64_t(x));
          }
        }
        if (int(k) == fi) faces.push_back(std::move(idx));
      }
      if (isVertex) {
        for (int c = 0; c < 3; ++c)
          if (!limits::within(v[c], limits::kCoordinate))
            in.fail(what, "coordinate " + std::to_string(v[c]) + " is not finite or outside " + limits::kCoordinate.text());
        vertices.push_back(v);
      }
    }
  }
  MeshData md;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    std::vector<Vec3> pts;
    for (std::uint64_t i : faces[f]) {
      if (i >= vertices.size())
        throw InputError(path + ": face " + std::to_string(f) + ": vertex index " + std::to_string(i) + " out of range (" +
                         std::to_string(vertices.size()) + " vertices)");
      pts.push_back(vertices[i]);
    }
    pushPolygon(md, pts, -1);
  }
  if (md.faces.empty()) throw InputError(path + ": PLY file has no faces");
  return md;
}

}  // namespace hr
