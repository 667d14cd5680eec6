// The .ghrs solution file, format version 2: the tagged-section container of hr/section_file.h with
// the core's sections "meta" (scene name, host, algorithm, object count), "materials", "cameras",
// "patches" and "elements", plus any opaque sections the solution carries (Solution::sections: an
// extension's state). Each section has its own CRC-32, so a damaged file is refused naming the section;
// after the checksums every value is validated again (ranges, indices, tree shape), so that even a
// file with valid checksums but wrong content (a fuzzer's, or a buggy writer's) cannot crash render.
#include <cstring>
#include <fstream>
#include <hr/echo.h>
#include <hr/input_file.h>
#include <hr/limits.h>
#include <hr/output.h>
#include <hr/section_file.h>
#include <hr/solution.h>

namespace hr {
namespace {

constexpr std::string_view kMagic{"GHRS\r\n\x1a\n", 8};
constexpr std::uint32_t kVersion = 2;
constexpr const char* kCoreSections[] = {"meta", "materials", "cameras", "patches", "elements"};
constexpr const char* kExtensionSection = "extension";  // Solution::extension, when the run had one

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
  std::string take() { return std::move(buf_); }

 private:
  std::string buf_;
};

/// Reads one section's payload; every failure names the file and the section.
class In {
 public:
  In(const Section& s, const std::string& path) : d_(s.payload), where_(path + ": section " + echo(s.name) + ": ") {}
  [[noreturn]] void fail(const std::string& msg) const { throw InputError(where_ + msg); }
  template <class T>
  T pod() {
    if (d_.size() - pos_ < sizeof(T)) fail("truncated (at byte " + std::to_string(pos_) + ")");
    T v;
    std::memcpy(&v, d_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string str() {
    auto n = pod<std::uint32_t>();
    if (d_.size() - pos_ < n) fail("truncated string");
    std::string s = d_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  double number(const limits::Range& r, const char* what) {
    double v = pod<double>();
    if (!limits::within(v, r)) fail(std::string(what) + " " + std::to_string(v) + " outside " + r.text());
    return v;
  }
  Vec3 vec(const limits::Range& r, const char* what) { return {number(r, what), number(r, what), number(r, what)}; }
  Polygon poly() {
    Polygon p;
    p.n = pod<std::int32_t>();
    if (p.n != 3 && p.n != 4) fail("polygon with " + std::to_string(p.n) + " corners");
    for (int i = 0; i < 4; ++i) p.v[i] = vec(limits::kCoordinate, "coordinate");
    return p;
  }
  /// A count of records of at least minBytes each: never more than the payload can hold.
  std::uint32_t count(std::size_t minBytes) {
    auto n = pod<std::uint32_t>();
    if (std::size_t(n) * minBytes > d_.size() - pos_) fail("count " + std::to_string(n) + " exceeds the section");
    return n;
  }
  void end() const {
    if (pos_ != d_.size()) fail(std::to_string(d_.size() - pos_) + " unexpected bytes at the end");
  }

 private:
  const std::string& d_;
  std::size_t pos_ = 0;
  std::string where_;
};

bool coreSection(const std::string& name) {
  if (name == kExtensionSection) return true;
  for (const char* c : kCoreSections)
    if (name == c) return true;
  return false;
}

}  // namespace

void setSection(Solution& s, const std::string& name, std::string bytes) {
  if (coreSection(name)) throw std::logic_error("section name " + name + " belongs to the core");
  for (auto& sec : s.sections)
    if (sec.name == name) {
      sec.payload = std::move(bytes);
      return;
    }
  s.sections.push_back({name, std::move(bytes)});
}

const std::string* findSection(const Solution& s, const std::string& name) {
  for (const auto& sec : s.sections)
    if (sec.name == name) return &sec.payload;
  return nullptr;
}

namespace {

/// The file's sections; the extension's bytes, which can be most of the file, are not copied (the
/// writer refers to them: `s` must outlive it).
void addSections(const Solution& s, SectionWriter& w, std::string& extensionHead) {
  Out meta;
  meta.str(s.sceneName), meta.str(s.host), meta.str(s.algorithm), meta.pod(s.objectCount);
  w.add("meta", meta.take());
  Out mats;
  mats.pod<std::uint32_t>(static_cast<std::uint32_t>(s.materials.size()));
  for (const Material& m : s.materials) {
    mats.str(m.name);
    mats.vec(m.diffuse), mats.vec(m.specular), mats.pod(m.exponent), mats.vec(m.emission);
  }
  w.add("materials", mats.take());
  Out cams;
  cams.pod<std::uint32_t>(static_cast<std::uint32_t>(s.cameras.size()));
  for (const Camera& c : s.cameras) {
    cams.str(c.name);
    cams.vec(c.eye), cams.vec(c.lookAt), cams.vec(c.up), cams.pod(c.fovYDeg);
    cams.pod<std::int32_t>(c.width), cams.pod<std::int32_t>(c.height);
  }
  w.add("cameras", cams.take());
  Out pats;
  pats.pod<std::uint32_t>(static_cast<std::uint32_t>(s.patches.size()));
  for (const Patch& p : s.patches) {
    pats.poly(p.poly);
    pats.vec(p.normal), pats.pod(p.area), pats.pod(p.material), pats.pod(p.object);
  }
  w.add("patches", pats.take());
  Out els;
  els.pod<std::uint32_t>(static_cast<std::uint32_t>(s.elements.size()));
  for (const SolutionElement& e : s.elements) {
    els.poly(e.poly);
    els.pod(e.patch), els.pod(e.firstChild), els.pod(e.level), els.vec(e.radiosity);
  }
  w.add("elements", els.take());
  if (!s.extension.name.empty()) {
    // The run's extension: its name in the extension table, its own format version, its bytes (as
    // Out::str writes a string: a u32 length, then the bytes).
    const std::uint64_t size = s.extension.write ? producedSize(s.extension.write) : s.extension.bytes.size();
    if (size > 0xFFFFFFFFu) throw std::runtime_error("the extension's data exceed 4 GiB");
    Out x;
    x.str(s.extension.name), x.pod(s.extension.version), x.pod<std::uint32_t>(std::uint32_t(size));
    extensionHead = x.take();
    if (s.extension.write)
      w.addProduced(kExtensionSection, extensionHead, s.extension.write, size);
    else
      w.addPieces(kExtensionSection, {extensionHead, s.extension.bytes});
  }
  for (const Section& sec : s.sections) w.addPieces(sec.name, {sec.payload});
}

}  // namespace

std::string serializeSolution(const Solution& s) {
  SectionWriter w(kMagic, kVersion);
  std::string head;
  addSections(s, w, head);
  return w.finish();
}

void saveSolution(const Solution& s, const std::string& path) {
  // Streamed to the file: a glossy solution's sections are not copied into one string first.
  SectionWriter w(kMagic, kVersion);
  std::string head;
  addSections(s, w, head);
  writeAtomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    w.write(out);
    out.close();
    if (!out) throw std::runtime_error(path + ": cannot write file");
  });
}

Solution parseSolution(std::string_view bytes, const std::string& path, bool verifyChecksums) {
  std::vector<Section> secs = readSections(bytes, kMagic, kVersion, path, verifyChecksums);
  const Section* core[5] = {};
  Solution s;
  for (const Section& sec : secs) {
    bool known = false;
    for (int k = 0; k < 5; ++k)
      if (sec.name == kCoreSections[k]) {
        if (core[k]) throw InputError(path + ": section " + echo(sec.name) + " appears twice");
        core[k] = &sec, known = true;
      }
    if (!known && sec.name == kExtensionSection) {
      if (!s.extension.name.empty()) throw InputError(path + ": section \"extension\" appears twice");
      In x(sec, path);
      s.extension.name = x.str(), s.extension.version = x.pod<std::uint32_t>(), s.extension.bytes = x.str();
      x.end();
      if (s.extension.name.empty()) x.fail("no extension name");
      known = true;
    }
    if (!known) {
      if (findSection(s, sec.name)) throw InputError(path + ": section " + echo(sec.name) + " appears twice");
      s.sections.push_back(sec);
    }
  }
  for (int k = 0; k < 5; ++k)
    if (!core[k]) throw InputError(path + ": section \"" + std::string(kCoreSections[k]) + "\" is missing");

  In meta(*core[0], path);
  s.sceneName = meta.str(), s.host = meta.str(), s.algorithm = meta.str();
  s.objectCount = meta.pod<std::uint32_t>();
  meta.end();

  In mats(*core[1], path);
  for (std::uint32_t n = mats.count(4 + 80), i = 0; i < n; ++i) {
    Material m;
    m.name = mats.str();
    m.diffuse = mats.vec(limits::kReflectance, "diffuse reflectance");
    m.specular = mats.vec(limits::kReflectance, "specular reflectance");
    m.exponent = mats.number(limits::kExponent, "exponent");
    m.emission = mats.vec(limits::kEmission, "emission");
    s.materials.push_back(m);
  }
  mats.end();

  In cams(*core[2], path);
  for (std::uint32_t n = cams.count(4 + 88), i = 0; i < n; ++i) {
    Camera c;
    c.name = cams.str();
    c.eye = cams.vec(limits::kCoordinate, "camera eye");
    c.lookAt = cams.vec(limits::kCoordinate, "camera look_at");
    c.up = cams.vec(limits::kCoordinate, "camera up");
    c.fovYDeg = cams.number(limits::kFovDeg, "camera fov_y_deg");
    c.width = cams.pod<std::int32_t>(), c.height = cams.pod<std::int32_t>();
    if (!limits::kImageSize.contains(c.width) || !limits::kImageSize.contains(c.height))
      cams.fail("camera " + echo(c.name) + ": image size outside " + limits::kImageSize.text());
    Vec3 f = c.lookAt - c.eye;
    if (glm::length(f) == 0.0 || glm::length(glm::cross(f, c.up)) == 0.0)
      cams.fail("camera " + echo(c.name) + ": degenerate view (eye = look_at or up parallel to the view)");
    s.cameras.push_back(c);
  }
  cams.end();
  if (s.cameras.empty()) cams.fail("no camera");

  In pats(*core[3], path);
  for (std::uint32_t n = pats.count(4 + 96 + 24 + 16), i = 0; i < n; ++i) {
    Patch p;
    p.poly = pats.poly();
    p.normal = pats.vec(limits::Range{"normal", -1.0 - 1e-9, 1.0 + 1e-9}, "normal component");
    p.area = pats.number(limits::Range{"area", 1e-300, 1e13}, "area");
    p.material = pats.pod<std::uint32_t>(), p.object = pats.pod<std::uint32_t>();
    if (std::abs(glm::length(p.normal) - 1.0) > 1e-6) pats.fail("patch " + std::to_string(i) + ": normal is not a unit vector");
    if (p.material >= s.materials.size()) pats.fail("patch " + std::to_string(i) + ": material index out of range");
    if (p.object >= s.objectCount) pats.fail("patch " + std::to_string(i) + ": object index out of range");
    s.patches.push_back(p);
  }
  pats.end();
  if (s.patches.empty()) pats.fail("no patch");

  In els(*core[4], path);
  const std::uint32_t n = els.count(4 + 96 + 12 + 24);
  for (std::uint32_t i = 0; i < n; ++i) {
    SolutionElement e;
    e.poly = els.poly();
    e.patch = els.pod<std::uint32_t>(), e.firstChild = els.pod<std::uint32_t>(), e.level = els.pod<std::uint32_t>();
    e.radiosity = els.vec(limits::Range{"radiosity", 0.0, 1e30}, "radiosity");
    s.elements.push_back(e);
  }
  els.end();
  // The element forest: element i < patches is the root of patch i; children come after their parent
  // (so walking down always ends), in groups of four of the same patch, one level deeper.
  if (s.elements.size() < s.patches.size()) els.fail("fewer elements than patches");
  for (std::uint32_t i = 0; i < n; ++i) {
    const SolutionElement& e = s.elements[i];
    const std::string at = "element " + std::to_string(i) + ": ";
    if (e.patch >= s.patches.size()) els.fail(at + "patch index out of range");
    if (i < s.patches.size() && (e.patch != i || e.level != 0)) els.fail(at + "not the root of patch " + std::to_string(i));
    if (e.level > 64) els.fail(at + "level " + std::to_string(e.level) + " beyond 64");
    if (e.leaf()) continue;
    if (e.firstChild <= i || e.firstChild < s.patches.size() || std::uint64_t(e.firstChild) + 4 > n)
      els.fail(at + "child index out of range");
    for (std::uint32_t k = 0; k < 4; ++k) {
      const SolutionElement& c = s.elements[e.firstChild + k];
      if (c.patch != e.patch || c.level != e.level + 1) els.fail(at + "child " + std::to_string(k) + " does not belong to it");
    }
  }
  try {
    reconstruct(s);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  return s;
}

Solution loadSolution(const std::string& path) {
  return parseSolution(readInputFile(path, "solution file", limits::kMaxSolutionBytes), path, true);
}

}  // namespace hr
