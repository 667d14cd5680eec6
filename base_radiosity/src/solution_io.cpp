// The .ghrs solution file: "GHRS" magic, a format version, then length-prefixed sections in
// little-endian order. Every read is bounds-checked so a truncated or foreign file is rejected with
// a message that says which.
#include <cstring>
#include <fstream>
#include <hr/output.h>
#include <hr/solution.h>
#include <sstream>

namespace hr {
namespace {

constexpr char kMagic[8] = {'G', 'H', 'R', 'S', '\r', '\n', 0x1a, '\n'};
constexpr std::uint32_t kVersion = 2;  // 2: the extension section

class Out {
 public:
  template <class T>
  void pod(const T& v) {
    buf_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void str(const std::string& s) {
    pod<std::uint32_t>(static_cast<std::uint32_t>(s.size()));
    buf_ += s;
  }
  void vec(const Vec3& v) { pod(v.x), pod(v.y), pod(v.z); }
  void poly(const Polygon& p) {
    pod<std::int32_t>(p.n);
    for (int i = 0; i < 4; ++i) vec(p.v[i]);
  }
  std::string buf_;
};

class In {
 public:
  In(std::string data, std::string path) : d_(std::move(data)), path_(std::move(path)) {}
  template <class T>
  T pod() {
    if (pos_ + sizeof(T) > d_.size()) throw InputError(path_ + ": truncated solution file (at byte " + std::to_string(pos_) + ")");
    T v;
    std::memcpy(&v, d_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string str() {
    auto n = pod<std::uint32_t>();
    if (pos_ + n > d_.size()) throw InputError(path_ + ": truncated solution file (string)");
    std::string s = d_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  Vec3 vec() {
    Vec3 v;
    v.x = pod<double>(), v.y = pod<double>(), v.z = pod<double>();
    if (!allFinite(v)) throw InputError(path_ + ": corrupt solution file (non-finite value)");
    return v;
  }
  Polygon poly() {
    Polygon p;
    p.n = pod<std::int32_t>();
    if (p.n != 3 && p.n != 4) throw InputError(path_ + ": corrupt solution file (polygon arity)");
    for (int i = 0; i < 4; ++i) p.v[i] = vec();
    return p;
  }
  std::uint32_t count(std::size_t minBytesEach) {
    auto n = pod<std::uint32_t>();
    if (std::size_t(n) * minBytesEach > d_.size() - pos_) throw InputError(path_ + ": truncated solution file (count)");
    return n;
  }
  bool atEnd() const { return pos_ == d_.size(); }
  std::string bytes(std::uint64_t n) {
    if (n > d_.size() - pos_) throw InputError(path_ + ": truncated solution file (extension section)");
    std::string b = d_.substr(pos_, n);
    pos_ += n;
    return b;
  }

 private:
  std::string d_;
  std::size_t pos_ = 0;
  std::string path_;
};

}  // namespace

void saveSolution(const Solution& s, const std::string& path) {
  Out o;
  o.buf_.append(kMagic, 8);
  o.pod(kVersion);
  o.str(s.sceneName);
  o.str(s.host);
  o.str(s.algorithm);
  o.pod(s.objectCount);
  o.pod<std::uint32_t>(static_cast<std::uint32_t>(s.materials.size()));
  for (const Material& m : s.materials) {
    o.str(m.name);
    o.vec(m.diffuse), o.vec(m.specular), o.pod(m.exponent), o.vec(m.emission);
  }
  o.pod<std::uint32_t>(static_cast<std::uint32_t>(s.cameras.size()));
  for (const Camera& c : s.cameras) {
    o.str(c.name);
    o.vec(c.eye), o.vec(c.lookAt), o.vec(c.up), o.pod(c.fovYDeg), o.pod<std::int32_t>(c.width), o.pod<std::int32_t>(c.height);
  }
  o.pod<std::uint32_t>(static_cast<std::uint32_t>(s.patches.size()));
  for (const Patch& p : s.patches) {
    o.poly(p.poly);
    o.vec(p.normal), o.pod(p.area), o.pod(p.material), o.pod(p.object);
  }
  o.pod<std::uint32_t>(static_cast<std::uint32_t>(s.elements.size()));
  for (const SolutionElement& e : s.elements) {
    o.poly(e.poly);
    o.pod(e.patch), o.pod(e.firstChild), o.pod(e.level), o.vec(e.radiosity);
  }
  // The extension's section: its name, its own format version and its bytes (empty name: none).
  o.buf_.append("EXTN", 4);
  o.str(s.extension.name);
  o.pod(s.extension.version);
  o.pod<std::uint64_t>(s.extension.bytes.size());
  o.buf_ += s.extension.bytes;
  o.buf_.append("END!", 4);
  writeFileAtomically(path, o.buf_);
}

Solution loadSolution(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path + ": cannot open solution file");
  std::stringstream ss;
  ss << f.rdbuf();
  std::string data = ss.str();
  if (data.size() < 12 || std::memcmp(data.data(), kMagic, 8) != 0)
    throw InputError(path + ": not a glossyhr solution file (bad magic)");
  In in(data, path);
  for (int i = 0; i < 8; ++i) in.pod<char>();
  auto version = in.pod<std::uint32_t>();
  if (version != kVersion)
    throw InputError(path + ": solution file version " + std::to_string(version) + " is not supported (expected " +
                     std::to_string(kVersion) + ")");
  Solution s;
  s.sceneName = in.str();
  s.host = in.str();
  s.algorithm = in.str();
  s.objectCount = in.pod<std::uint32_t>();
  for (std::uint32_t n = in.count(4), i = 0; i < n; ++i) {
    Material m;
    m.name = in.str();
    m.diffuse = in.vec(), m.specular = in.vec(), m.exponent = in.pod<double>(), m.emission = in.vec();
    s.materials.push_back(m);
  }
  for (std::uint32_t n = in.count(4), i = 0; i < n; ++i) {
    Camera c;
    c.name = in.str();
    c.eye = in.vec(), c.lookAt = in.vec(), c.up = in.vec(), c.fovYDeg = in.pod<double>();
    c.width = in.pod<std::int32_t>(), c.height = in.pod<std::int32_t>();
    if (c.width < 1 || c.height < 1 || c.width > 16384 || c.height > 16384) throw InputError(path + ": corrupt camera size");
    s.cameras.push_back(c);
  }
  for (std::uint32_t n = in.count(100), i = 0; i < n; ++i) {
    Patch p;
    p.poly = in.poly();
    p.normal = in.vec(), p.area = in.pod<double>(), p.material = in.pod<std::uint32_t>(), p.object = in.pod<std::uint32_t>();
    if (p.material >= s.materials.size()) throw InputError(path + ": corrupt solution file (material index)");
    s.patches.push_back(p);
  }
  for (std::uint32_t n = in.count(100), i = 0; i < n; ++i) {
    SolutionElement e;
    e.poly = in.poly();
    e.patch = in.pod<std::uint32_t>(), e.firstChild = in.pod<std::uint32_t>(), e.level = in.pod<std::uint32_t>();
    e.radiosity = in.vec();
    if (e.patch >= s.patches.size() || (e.firstChild != kNone && e.firstChild + 4 > n))
      throw InputError(path + ": corrupt solution file (element index)");
    s.elements.push_back(e);
  }
  if (s.elements.size() < s.patches.size()) throw InputError(path + ": corrupt solution file (element count)");
  if (in.pod<std::uint32_t>() != 0x4E545845u) throw InputError(path + ": corrupt solution file (extension section)");
  s.extension.name = in.str();
  s.extension.version = in.pod<std::uint32_t>();
  s.extension.bytes = in.bytes(in.pod<std::uint64_t>());
  if (in.pod<std::uint32_t>() != 0x21444E45u || !in.atEnd()) throw InputError(path + ": corrupt solution file (trailer)");
  reconstruct(s);
  return s;
}

}  // namespace hr
