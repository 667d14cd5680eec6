// The extension's section of the solution file: the distributions of the glossy leaves (display
// needs nothing else), under a checksum. Loading trusts nothing: a damaged, truncated or foreign
// section, or one that does not fit the loaded solution's elements, is refused with hr::InputError
// before any state changes, and nothing non-finite can come out of it.
// Version 2 (--basis auto): the header says whether bases were chosen per material, and every record
// names its own basis, so one section holds distributions of several bases. Version 1 sections (one
// basis, no per-record tag) are refused by the host with the versions named: re-solve to update.
// Version 3: after the distributions, the leaves' shown light (shown_light.h: the brightest
// incident samples the display sharpens highlights with), so a rendered file shows what the solve
// showed. Version 4: each shown sample also names its sender's normal (zero for none). Version 5:
// and its sender's shape (hr/sender_shape.h: the half-axis, then the half-width; zero for none).
// Version 6: a shown light's joined samples' pieces as the solve deposited them (their count, then
// each as a sample is written) before its samples, and each sample preceded by its first piece and
// piece count (0: none).
#include <glossy/illumination_samples.h>
#include <glossy/is_options.h>
#include <glossy/serial.h>

#include <map>
#include <sstream>
#include <streambuf>

namespace glossy {

namespace {

constexpr std::uint32_t kMagic = 0x53494C47u;  // "GLIS"
constexpr const char* kWhat = "solution file, section of extension 'is'";

[[noreturn]] void refuse(const std::string& why) { throw hr::InputError(std::string(kWhat) + ": " + why); }

/// FNV-1a, 64 bits: any change of one byte changes it, and random damage passes with odds 2^-64.
std::uint64_t fnv1a(std::string_view bytes, std::uint64_t h = 0xcbf29ce484222325ull) {
  for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

/// Counts what is written to it (the size a record will take).
class CountingBuffer : public std::streambuf {
 public:
  std::uint64_t bytes() const { return n_; }

 protected:
  std::streamsize xsputn(const char*, std::streamsize n) override { return n_ += std::uint64_t(n), n; }
  int_type overflow(int_type c) override { return traits_type::eq_int_type(c, traits_type::eof()) ? c : (++n_, c); }

 private:
  std::uint64_t n_ = 0;
};

/// Forwards what is written to it and carries its FNV-1a hash (fnv1a's, byte for byte) and count.
class HashingBuffer : public std::streambuf {
 public:
  explicit HashingBuffer(std::streambuf* next) : next_(next) {}
  std::uint64_t hash() const { return h_; }
  std::uint64_t bytes() const { return n_; }

 protected:
  std::streamsize xsputn(const char* p, std::streamsize n) override {
    h_ = fnv1a(std::string_view(p, std::size_t(n)), h_);
    n_ += std::uint64_t(n);
    return next_->sputn(p, n);
  }
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return c;
    char ch = traits_type::to_char_type(c);
    return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
  }

 private:
  std::streambuf* next_;
  std::uint64_t h_ = fnv1a({});
  std::uint64_t n_ = 0;
};

/// A read-only stream over bytes the caller keeps: loading a large section read it through a copy.
class ViewBuffer : public std::streambuf {
 public:
  explicit ViewBuffer(std::string_view v) {
    char* p = const_cast<char*>(v.data());  // get area only: nothing is written through it
    setg(p, p, p + v.size());
  }

 protected:
  // tellg and seekg, within the bytes (as an istringstream over a copy of them would allow).
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override {
    if (which & std::ios_base::out) return pos_type(off_type(-1));
    const off_type base = dir == std::ios_base::beg ? 0 : dir == std::ios_base::cur ? gptr() - eback() : egptr() - eback();
    const off_type to = base + off;
    if (to < 0 || to > egptr() - eback()) return pos_type(off_type(-1));
    setg(eback(), eback() + to, egptr());
    return pos_type(to);
  }
  pos_type seekpos(pos_type p, std::ios_base::openmode which) override { return seekoff(off_type(p), std::ios_base::beg, which); }
};

std::uint64_t u64At(std::string_view b, std::size_t at) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < 8; ++i) v |= std::uint64_t(static_cast<unsigned char>(b[at + i])) << (8 * i);
  return v;
}
std::uint32_t u32At(std::string_view b, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < 4; ++i) v |= std::uint32_t(static_cast<unsigned char>(b[at + i])) << (8 * i);
  return v;
}

/// The byte size a record must have, from its own header: refuses before anything is allocated.
std::uint64_t expectedRecordBytes(std::string_view r, Basis basis) {
  if (r.size() < 12) refuse("distribution record too short");
  switch (basis) {
    case Basis::Haar: {
      if (r.size() < 16) refuse("distribution record too short");
      std::uint64_t count = u64At(r, 8);
      if (count > (std::uint64_t(1) << 32)) refuse("Haar node count out of range");
      return 16 + 16 * count;
    }
    case Basis::Tetra: {
      std::uint32_t level = u32At(r, 8);
      if (level > std::uint32_t(TetraMesh::kMaxLevel)) refuse("tetrahedron level out of range");
      return 12 + 12 * (2 * (std::uint64_t(1) << (2 * level)) + 2);
    }
    default: {
      std::uint32_t order = u32At(r, 8);
      if (order > std::uint32_t(ShDistribution::kMaxOrder)) refuse("spherical harmonics order out of range");
      return 12 + 12 * std::uint64_t(order) * order;
    }
  }
}

/// Checks a Haar tree beyond its structure: depth within the stated level, no negative values, and
/// nothing below the local horizon (faces 4-7 are folded zero leaves in a leaf's own frame).
void checkHaar(const HaarDistribution& h, int maxLevel) {
  auto nodes = h.nodes();
  std::vector<std::uint8_t> level(nodes.size(), 0);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    for (float v : nodes[i].rgb)
      if (!(v >= 0.0f)) refuse("negative intensity in a Haar distribution");
    if (nodes[i].child == 0) continue;
    if (level[i] >= maxLevel) refuse("Haar distribution deeper than its stated maximum level");
    for (std::uint32_t k = 0; k < 4; ++k) level[nodes[i].child + k] = std::uint8_t(level[i] + 1);
  }
  for (std::size_t f = 4; f < 8; ++f)
    if (nodes[f].child != 0 || nodes[f].rgb[0] != 0.0f || nodes[f].rgb[1] != 0.0f || nodes[f].rgb[2] != 0.0f)
      refuse("light below a leaf's horizon");
}

/// Whether a shown sample's piece range lies within the m pieces of its light (none: first piece 0).
bool piecesFit(std::uint64_t first, std::uint64_t pieces, std::uint64_t m) {
  return pieces > 0 ? first < m && pieces <= m - first : first == 0;
}

Vec3 readVec(std::istream& in) {
  const double x = serial::readF64(in), y = serial::readF64(in), z = serial::readF64(in);
  return Vec3(x, y, z);
}

}  // namespace

void IlluminationSamples::readShown(std::istream& in, Table& table) const {
  const std::uint64_t count = serial::readU64(in);
  if (count > table.size()) refuse("more shown lights than the solution has elements");
  std::int64_t previous = -1;
  for (std::uint64_t k = 0; k < count; ++k) {
    const std::uint32_t index = serial::readU32(in), n = serial::readU32(in);
    const std::string where = "element " + std::to_string(index) + "'s shown light";
    if (std::int64_t(index) <= previous) refuse(where + ": elements out of order or repeated");
    previous = index;
    if (index >= table.size() || !table[index] || !std::holds_alternative<HaarDistribution>(table[index]->dist))
      refuse(where + ": no Haar distribution of its own");
    if (n == 0 || n > std::uint32_t(kShownSamples)) refuse(where + ": " + std::to_string(n) + " samples");
    auto sh = std::make_shared<ShownLight>();
    sh->specular = readVec(in);
    sh->exponent = serial::readF64(in);
    sh->total = serial::readF64(in);
    sh->level = int(serial::readU32(in));
    sh->senderPoints = int(serial::readU32(in));
    if (!hr::allFinite(sh->specular) || !glm::all(glm::greaterThanEqual(sh->specular, Rgb(0.0))) ||
        !(sh->exponent >= 0.0) || !std::isfinite(sh->exponent) || sh->level < 0 || sh->level > kMaxDirLevel || !(sh->total > 0.0) || !std::isfinite(sh->total) ||
        sh->senderPoints < 0 || sh->senderPoints > kSenderPoints)
      refuse(where + ": values out of range");
    // One sample's or piece's fields, checked.
    auto readSample = [&](const char* kind, std::uint64_t j) {
      ShownLight::Sample y;
      const Vec3 from = readVec(in), normal = readVec(in), toSender = readVec(in), irradiance = readVec(in);
      const Vec3 senderNormal = readVec(in);
      const double distance = serial::readF64(in), radius = serial::readF64(in);
      const Vec3 axis = readVec(in);
      const double halfWidth = serial::readF64(in);
      const double axisLength = glm::length(axis);
      // A shape lies in its sender's plane, and only a flat sender has one.
      const bool inPlane =
          senderNormal != Vec3(0.0) && std::abs(glm::dot(axis, senderNormal)) <= 1e-3 * axisLength;
      const bool shapeOk = hr::allFinite(axis) && axisLength < 1e30 && halfWidth >= 0.0 && halfWidth < 1e30 &&
                           (axis == Vec3(0.0) ? halfWidth == 0.0 : inPlane);
      if (!hr::allFinite(from) || !hr::allFinite(normal) || std::abs(glm::length(normal) - 1.0) > 1e-6 ||
          !hr::allFinite(toSender) || std::abs(glm::length(toSender) - 1.0) > 1e-6 || !hr::allFinite(irradiance) ||
          !glm::all(glm::greaterThanEqual(irradiance, Rgb(0.0))) || !(distance >= 0.0) || !(distance < 1e30) ||
          !(radius >= 0.0) || !(radius < 1e30) || glm::any(glm::greaterThan(glm::abs(from), Vec3(1e30))) ||
          glm::any(glm::greaterThan(irradiance, Rgb(1e30))) || !hr::allFinite(senderNormal) ||
          (senderNormal != Vec3(0.0) && std::abs(glm::length(senderNormal) - 1.0) > 1e-6) || !shapeOk)
        refuse(where + ": " + kind + " " + std::to_string(j) + " out of range");
      y.from = glm::vec3(from), y.normal = glm::vec3(normal), y.toSender = glm::vec3(toSender);
      y.irradiance = glm::vec3(irradiance), y.distance = float(distance), y.radius = float(radius);
      y.senderNormal = glm::vec3(senderNormal);
      y.senderShape = {glm::vec3(axis), float(halfWidth)};
      return y;
    };
    // The joined samples' pieces first (read one by one: a damaged count runs into the end of the
    // section, not into memory), then the samples, each naming its pieces.
    const std::uint64_t m = serial::readU64(in);
    for (std::uint64_t j = 0; j < m; ++j) sh->deposited.push_back(readSample("piece", j));
    for (std::uint32_t j = 0; j < n; ++j) {
      const std::uint32_t first = serial::readU32(in), pieces = serial::readU32(in);
      if (!piecesFit(first, pieces, m))
        refuse(where + ": sample " + std::to_string(j) + " names pieces beyond the " + std::to_string(m) +
               " there are");
      ShownLight::Sample y = readSample("sample", j);
      y.firstPiece = first, y.pieces = pieces;
      sh->samples.push_back(y);
    }
    table[index]->shown = std::move(sh);
  }
}

void IlluminationSamples::save(std::ostream& sink) const {
  std::vector<std::uint32_t> leaves;
  for (std::size_t i = 0; i < elements_.size(); ++i)
    if (elements_[i] && isLeaf(i)) leaves.push_back(std::uint32_t(i));
  auto record = [&](std::uint32_t i, std::ostream& out) {
    std::visit([&](const auto& d) { d.serialize(out); }, elements_[i]->dist);
  };
  // Streamed into the file (the section runs to gigabytes on the Soda Shoppe); each record's size,
  // which precedes it, is counted first.
  std::vector<std::uint64_t> sizes(leaves.size());
  std::size_t total = 4 * 4 + 8 + 4 * 4 + 8 + 8;  // header, leaf count, checksum
  for (std::size_t k = 0; k < leaves.size(); ++k) {
    CountingBuffer count;
    std::ostream c(&count);
    record(leaves[k], c);
    sizes[k] = count.bytes();
    total += 4 + 4 + 8 + sizes[k];
  }
  // The shown light: its leaves in order, each with its material's constants and its samples.
  auto shownBlock = [&](std::ostream& out) {
    auto f64 = [&](double x) { serial::writeF64(out, x); };
    auto vec = [&](const Vec3& v) { f64(v.x), f64(v.y), f64(v.z); };
    std::uint64_t count = 0;
    for (std::uint32_t i : leaves) count += elements_[i]->shown ? 1 : 0;
    serial::writeU64(out, count);
    for (std::uint32_t i : leaves) {
      const ShownLight* sh = elements_[i]->shown.get();
      if (!sh) continue;
      serial::writeU32(out, i);
      serial::writeU32(out, std::uint32_t(sh->samples.size()));
      vec(sh->specular), f64(sh->exponent), f64(sh->total);
      serial::writeU32(out, std::uint32_t(sh->level));
      serial::writeU32(out, std::uint32_t(sh->senderPoints));
      auto sample = [&](const ShownLight::Sample& x) {
        vec(Vec3(x.from)), vec(Vec3(x.normal)), vec(Vec3(x.toSender)), vec(Vec3(x.irradiance)), vec(Vec3(x.senderNormal)),
            f64(x.distance), f64(x.radius), vec(Vec3(x.senderShape.axis)), f64(x.senderShape.halfWidth);
      };
      serial::writeU64(out, sh->deposited.size());
      for (const ShownLight::Sample& x : sh->deposited) sample(x);
      for (const ShownLight::Sample& x : sh->samples) {
        // What the reader refuses is never written.
        if (!piecesFit(x.firstPiece, x.pieces, sh->deposited.size()))
          throw std::logic_error("solution section: a shown sample names pieces it does not have");
        serial::writeU32(out, x.firstPiece), serial::writeU32(out, x.pieces);
        sample(x);
      }
    }
  };
  {
    CountingBuffer count;
    std::ostream c(&count);
    shownBlock(c);
    total += count.bytes();
  }
  HashingBuffer hashing(sink.rdbuf());
  std::ostream out(&hashing);
  serial::writeU32(out, kMagic);
  serial::writeU32(out, formatVersion());
  serial::writeU32(out, basis_.automatic ? 1u : 0u);
  serial::writeU32(out, std::uint32_t(basis_.basis));
  serial::writeF64(out, basis_.haar.eps);
  serial::writeU32(out, std::uint32_t(basis_.haar.minLevel));
  serial::writeU32(out, std::uint32_t(basis_.haar.maxLevel));
  serial::writeU32(out, std::uint32_t(basis_.tetraLevel));
  serial::writeU32(out, std::uint32_t(basis_.shOrder));
  serial::writeU64(out, leaves.size());
  for (std::size_t k = 0; k < leaves.size(); ++k) {
    serial::writeU32(out, leaves[k]);
    serial::writeU32(out, std::uint32_t(elements_[leaves[k]]->dist.index()));
    serial::writeU64(out, sizes[k]);
    record(leaves[k], out);
  }
  shownBlock(out);
  out.flush();
  serial::writeU64(sink, hashing.hash());
  if (hashing.bytes() + 8 != total) throw std::logic_error("solution section: counted and written sizes differ");
  if (!out || !sink) sink.setstate(std::ios::badbit);
}

void IlluminationSamples::load(std::string_view bytes, const hr::HostView& view) {
  if (bytes.size() < 8 + 44) refuse("truncated (" + std::to_string(bytes.size()) + " bytes)");
  std::string_view body = bytes.substr(0, bytes.size() - 8);
  if (fnv1a(body) != u64At(bytes, bytes.size() - 8)) refuse("checksum mismatch: the section is damaged or truncated");
  ViewBuffer bodyView(body);
  std::istream in(&bodyView);
  BasisSpec b = defaultIsBasis();
  std::vector<std::unique_ptr<NodeLight>> table(view.elementCount());
  std::map<std::uint32_t, Basis> seen;  // material -> the basis its records are in
  try {
    if (serial::readU32(in) != kMagic) refuse("not an Illumination Samples section");
    std::uint32_t version = serial::readU32(in);
    if (version != formatVersion())
      refuse("format version " + std::to_string(version) + ", this build reads version " + std::to_string(formatVersion()));
    std::uint32_t automatic = serial::readU32(in);
    if (automatic > 1) refuse("bad automatic-basis flag " + std::to_string(automatic));
    b.automatic = automatic == 1;
    std::uint32_t basis = serial::readU32(in);
    if (basis > 2) refuse("unknown basis " + std::to_string(basis));
    b.basis = Basis(basis);
    b.haar.eps = serial::readF64(in);
    b.haar.minLevel = int(std::min<std::uint32_t>(serial::readU32(in), 1000));
    b.haar.maxLevel = int(std::min<std::uint32_t>(serial::readU32(in), 1000));
    b.tetraLevel = int(std::min<std::uint32_t>(serial::readU32(in), 1000));
    b.shOrder = int(std::min<std::uint32_t>(serial::readU32(in), 1000));
    validateIsBasis(b, kWhat);
    std::uint64_t count = serial::readU64(in);
    if (count > view.elementCount()) refuse("more distributions than the solution has elements");
    std::int64_t previous = -1;
    for (std::uint64_t e = 0; e < count; ++e) {
      std::uint32_t index = serial::readU32(in);
      std::uint32_t recordBasis = serial::readU32(in);
      std::uint64_t size = serial::readU64(in);
      std::string where = "element " + std::to_string(index);
      if (recordBasis > 2) refuse(where + ": unknown basis " + std::to_string(recordBasis));
      const Basis rb = Basis(recordBasis);
      if (!b.automatic && rb != b.basis) refuse(where + ": a " + basisName(rb) + " record in a " + basisName(b.basis) + " section");
      if (std::int64_t(index) <= previous) refuse(where + ": elements out of order or repeated");
      previous = index;
      if (index >= view.elementCount()) refuse(where + ": no such element in the solution");
      hr::NodeInfo info = view.info(hr::NodeId{index});
      if (!info.leaf || !info.planar || info.material >= view.materialCount() || !(info.area > 0.0) ||
          !std::isfinite(info.area) || !hr::allFinite(info.normal) || std::abs(glm::length(info.normal) - 1.0) > 1e-6)
        refuse(where + ": not a planar leaf of the solution");
      if (!simulates(view.material(info.material))) refuse(where + ": its material is not glossy");
      if (seen.emplace(info.material, rb).first->second != rb)
        refuse(where + ": material " + std::to_string(info.material) + " holds records in two bases");
      std::size_t at = std::size_t(in.tellg());
      if (size > body.size() - at) refuse(where + ": record runs past the end of the section");
      std::string_view rec = body.substr(at, size);
      if (expectedRecordBytes(rec, rb) != size) refuse(where + ": record size does not match its contents");
      ViewBuffer recView(rec);
      std::istream rin(&recView);
      auto l = std::make_unique<NodeLight>();
      switch (rb) {
        case Basis::Haar: {
          HaarDistribution h = HaarDistribution::deserialize(rin);
          checkHaar(h, b.haar.maxLevel);
          l->dist = std::move(h);
          break;
        }
        case Basis::Tetra: {
          TetraDistribution t = TetraDistribution::deserialize(rin);
          if (t.level() != b.tetraLevel) refuse(where + ": tetrahedron level differs from the section's");
          for (std::size_t i = 0; i < t.mesh().vertexCount(); ++i)
            if (!glm::all(glm::greaterThanEqual(t.vertexValue(i), Rgb(0.0)))) refuse(where + ": negative intensity");
          l->dist = std::move(t);
          break;
        }
        default: {
          ShDistribution s = ShDistribution::deserialize(rin);
          if (s.order() != b.shOrder) refuse(where + ": spherical harmonics order differs from the section's");
          l->dist = std::move(s);
          break;
        }
      }
      in.seekg(std::streamoff(at + size));
      l->normal = info.normal;
      l->area = info.area;
      l->frame = rb == Basis::Haar ? Frame::around(info.normal) : Frame::world();
      finish(*l);
      if (!hr::allFinite(l->power) || !hr::allFinite(l->peak)) refuse(where + ": values out of range");
      table[index] = std::move(l);
    }
    readShown(in, table);
    if (std::size_t(in.tellg()) != body.size()) refuse("bytes after the shown light");
  } catch (const hr::InputError&) {
    throw;
  } catch (const std::exception& e) {
    refuse(e.what());
  }
  // Everything read: only now replace the state. The section states the basis its data are in.
  basis_ = b;
  finestLevel_ = b.haar.maxLevel;  // the finest level saved: a cap for the materials' own levels
  budgetLevels_ = -1;
  view_ = &view;
  chooseBases(view);  // materials without records; those with records keep the basis they were solved in
  for (const auto& [material, basis] : seen) materialBasis_[material] = basis;
  elements_ = std::move(table);
  clusters_.clear();
  unshotElements_.clear();
  unshotClusters_.clear();
  change_.clear();
  resize(view.elementCount(), view.clusterCount());
}

}  // namespace glossy
