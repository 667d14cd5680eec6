// The MGF reader: contexts (vertex, colour, material, transform, object), includes, transform arrays,
// and the geometric entities. Vertices are transformed at use, not at definition (as the format
// says); materials are snapshotted into scene materials when geometry uses them, so a material
// changed later gives later geometry a new scene material. See docs/mgf.md for the conversions.
#include <hr/echo.h>
#include <hr/geometry.h>
#include <hr/input_file.h>
#include <hr/limits.h>
#include <hr/mgf.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

namespace hr {

namespace fs = std::filesystem;

Vec3 cieToRgbUnclipped(double x, double y, double Y);

namespace {

constexpr double kWhiteEfficacy = 179.0;  // lm/W, Radiance's and RenderPark's white light
constexpr double kMaxExponent = 10000.0;  // Phong exponent for a perfect mirror (alpha = 0)
// The spectrum locus never comes below y = 0.0048: a smaller y is no colour, and x / y would overflow.
constexpr double kMinChromaY = 1e-3;
constexpr std::size_t kMaxNesting = 1000;  // xf contexts and includes open at once (recursion depth)

struct Colour {
  double x = 1.0 / 3.0, y = 1.0 / 3.0;
};

struct MgfMaterial {
  int sides = 2;
  double rd = 0, td = 0, ed = 0, rs = 0, rsAlpha = 0, ts = 0, tsAlpha = 0;
  Colour cd, ctd, ced, crs, cts;
  int version = 0;
};

struct Vertex {
  Vec3 p{0.0}, n{0.0};
};

struct Line {
  std::size_t number;
  std::vector<std::string> tok;
};

class MgfReader {
 public:
  MgfReader(Scene& s, const glm::dmat4& base, const std::string& where) : scene_(s), base_(base), where_(where) {}

  void readFile(const std::string& path, const glm::dmat4& xf) {
    std::string text;
    try {
      text = readInputFile(path, "MGF file", limits::kMaxMgfBytes);
    } catch (const InputError& e) {
      throw InputError(where_ + e.what());
    }
    readText(text, path, xf);
  }

  void readText(std::string text, const std::string& path, const glm::dmat4& xf) {
    std::error_code ec;
    std::string canon = fs::weakly_canonical(fs::path(path), ec).string();
    if (ec) canon = path;
    if (std::find(files_.begin(), files_.end(), canon) != files_.end())
      throw InputError(where_ + path + ": recursive include");
    if (files_.size() >= kMaxNesting) throw InputError(where_ + path + ": includes nested too deeply");
    stripUtf8Bom(text);
    std::istringstream in(std::move(text));
    std::vector<Line> lines;
    std::string acc, raw;
    std::size_t n = 0, start = 0;
    while (std::getline(in, raw)) {
      ++n;
      if (!raw.empty() && raw.back() == '\r') raw.pop_back();
      if (acc.empty()) start = n;
      if (!raw.empty() && raw.back() == '\\') {  // continuation
        acc += raw.substr(0, raw.size() - 1) + " ";
        continue;
      }
      acc += raw;
      std::istringstream ss(acc);
      Line l{start, {}};
      for (std::string t; ss >> t;) l.tok.push_back(t);
      acc.clear();
      if (l.tok.empty() || l.tok[0][0] == '#') continue;
      lines.push_back(std::move(l));
    }
    files_.push_back(canon);
    paths_.push_back(path);
    xf_.push_back(xf);
    std::size_t depth = xf_.size();
    run(lines, 0, lines.size());
    if (xf_.size() != depth)
      throw InputError(where_ + path + ": end of file inside an xf context (" + std::to_string(xf_.size() - depth) +
                       " unmatched xf)");
    xf_.pop_back();
    paths_.pop_back();
    files_.pop_back();
  }

  void finish() {
    auto list = [](const std::set<std::string>& s) {
      std::string r;
      for (const auto& n : s) r += (r.empty() ? "" : ", ") + n;
      return r;
    };
    if (!transmissive_.empty())
      scene_.dropped.push_back("transmission (td, ts) not simulated, dropped for " + list(transmissive_) +
                               "; largest transmitted fraction " + fmt(maxTransmitted_));
    if (!mirrors_.empty())
      scene_.dropped.push_back("perfect mirrors (rs roughness 0) approximated by Phong exponent " + fmt(kMaxExponent) +
                               ": " + list(mirrors_));
    if (!gaining_.empty())
      scene_.dropped.push_back("materials whose rd + td + rs + ts exceeds 1 (energy-gaining) scaled to 1: " +
                               list(gaining_));
    if (!scaled_.empty())
      scene_.dropped.push_back("colours whose RGB reflectance exceeded 1 in a channel scaled to 1: " + list(scaled_));
    if (!clipped_.empty()) scene_.dropped.push_back("out-of-gamut colours clipped to Rec. 709: " + list(clipped_));
    if (spectra_ > 0)
      scene_.dropped.push_back(std::to_string(spectra_) +
                               " cspec spectra converted to chromaticity with an analytic fit of the CIE 1931 "
                               "matching functions (a few per cent off the tables)");
    if (ignored_ > 0)
      scene_.dropped.push_back(std::to_string(ignored_) + " entities without effect here ignored (ir, ies)");
    if (twoSided_ > 0)
      scene_.dropped.push_back(std::to_string(twoSided_) +
                               " two-sided open surfaces (sides 2) kept one-sided, front by the right-hand rule");
  }

 private:
  // ---- errors and numbers --------------------------------------------------------------------
  [[noreturn]] void fail(const Line& l, const std::string& msg) const {
    std::string entity = l.tok[0].size() <= 16 ? l.tok[0] : echo(l.tok[0]);
    throw InputError(where_ + paths_.back() + ": line " + std::to_string(l.number) + ": " + entity + ": " + msg);
  }
  static std::string fmt(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }
  double num(const Line& l, std::size_t i) const {
    if (i >= l.tok.size()) fail(l, "missing argument " + std::to_string(i));
    const std::string& t = l.tok[i];
    char* end = nullptr;
    double v = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size() || !std::isfinite(v))
      fail(l, "argument " + std::to_string(i) + " " + echo(t) + " is not a finite number");
    return v;
  }
  /// A number inside a range of the limits table.
  double bounded(const Line& l, std::size_t i, const limits::Range& r) const {
    double v = num(l, i);
    if (!r.contains(v)) fail(l, "argument " + std::to_string(i) + " (" + fmt(v) + ") outside the allowed range " + r.text());
    return v;
  }
  /// A repeat count (xf -i, -a): an integer in [lo, kMaxMgfIterate].
  int count(const Line& l, std::size_t i, int lo) const {
    double v = num(l, i);
    if (v != std::floor(v) || v < lo || v > limits::kMaxMgfIterate)
      fail(l, "count " + fmt(v) + " is not an integer in [" + std::to_string(lo) + ", " +
                  std::to_string(limits::kMaxMgfIterate) + "]");
    return static_cast<int>(v);
  }
  /// Bounded work: every entity evaluated (array copies included) counts.
  void work(const Line& l, std::uint64_t units) {
    afford(l, units);
    work_ += units;
  }
  void afford(const Line& l, std::uint64_t units) const {
    if (work_ + units > limits::kMaxMgfWork)
      fail(l, "more than " + std::to_string(limits::kMaxMgfWork) +
                  " entity evaluations (transform arrays too large for the documented limit)");
  }
  void arity(const Line& l, std::size_t lo, std::size_t hi) const {
    std::size_t n = l.tok.size() - 1;
    if (n < lo || n > hi)
      fail(l, "expected " + (lo == hi ? std::to_string(lo) : std::to_string(lo) + "-" + std::to_string(hi)) +
                  " arguments, got " + std::to_string(n));
  }

  // ---- transforms -------------------------------------------------------------------------------
  /// Parses transform arguments [from, to): the transforms apply in the order given.
  glm::dmat4 xform(const Line& l, std::size_t from, std::size_t to) const {
    glm::dmat4 m(1.0);
    for (std::size_t i = from; i < to;) {
      const std::string& a = l.tok[i];
      glm::dmat4 t(1.0);
      if (a == "-t") {
        t = glm::translate(glm::dmat4(1.0), Vec3(bounded(l, i + 1, limits::kCoordinate), bounded(l, i + 2, limits::kCoordinate),
                                                 bounded(l, i + 3, limits::kCoordinate)));
        i += 4;
      } else if (a == "-rx" || a == "-ry" || a == "-rz") {
        Vec3 axis(a == "-rx", a == "-ry", a == "-rz");
        t = glm::rotate(glm::dmat4(1.0), glm::radians(bounded(l, i + 1, limits::kAngleDeg)), axis);
        i += 2;
      } else if (a == "-s") {
        double s = bounded(l, i + 1, limits::kScale);
        if (s == 0.0) fail(l, "-s 0 collapses the geometry");
        t = glm::scale(glm::dmat4(1.0), Vec3(s));
        i += 2;
      } else if (a == "-mx" || a == "-my" || a == "-mz") {
        t = glm::scale(glm::dmat4(1.0), Vec3(a == "-mx" ? -1 : 1, a == "-my" ? -1 : 1, a == "-mz" ? -1 : 1));
        i += 1;
      } else if (a == "-i") {
        // Iterate: the following transforms (up to the next -i or -a) apply N times.
        int n = count(l, i + 1, 0);
        std::size_t j = i + 2;
        while (j < to && l.tok[j] != "-i" && l.tok[j] != "-a") ++j;
        glm::dmat4 once = xform(l, i + 2, j);
        for (int k = 0; k < n; ++k) t = once * t;
        i = j;
      } else {
        fail(l, "unknown transform argument \"" + a + "\"");
      }
      m = t * m;
    }
    return m;
  }
  glm::dmat4 current() const {
    glm::dmat4 m = base_;
    for (const auto& x : xf_) m = m * x;
    return m;
  }

  // ---- the entity loop ----------------------------------------------------------------------------
  void run(const std::vector<Line>& lines, std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const Line& l = lines[i];
      const std::string& k = l.tok[0];
      work(l, 1);
      if (k == "xf" && xf_.size() >= kMaxNesting) fail(l, "transform contexts nested too deeply");
      if (k == "xf") {
        if (l.tok.size() == 1) {
          if (xf_.size() <= depthFloor()) fail(l, "xf end without a matching xf");
          xf_.pop_back();
          continue;
        }
        auto arr = std::find(l.tok.begin(), l.tok.end(), "-a");
        if (arr == l.tok.end()) {
          xf_.push_back(xform(l, 1, l.tok.size()));
          continue;
        }
        // An array: the enclosed lines up to the matching "xf" repeat N times, copy k with the
        // array's transform applied k times (after the transforms that precede -a).
        std::size_t j = closing(lines, i, e);
        if (j >= e) fail(l, "array without its closing xf");
        std::size_t at = std::size_t(arr - l.tok.begin());
        glm::dmat4 pre = xform(l, 1, at);
        int n = count(l, at + 1, 1);
        // The copies evaluate the enclosed lines n times, nested arrays multiplied out: refuse up
        // front what the limit cannot hold, instead of running into it after minutes.
        afford(l, std::min<std::uint64_t>(limits::kMaxMgfWork + 1, std::uint64_t(n) * cost(lines, i + 1, j)));
        glm::dmat4 step = xform(l, at + 2, l.tok.size()), acc(1.0);
        for (int c = 0; c < n; ++c) {
          xf_.push_back(acc * pre);
          std::size_t depth = xf_.size();
          run(lines, i + 1, j);
          if (xf_.size() != depth) fail(l, "unbalanced xf inside the array");
          xf_.pop_back();
          acc = step * acc;
        }
        i = j;
      } else if (k == "o") {
        if (l.tok.size() == 1) {
          if (!groups_.empty()) groups_.pop_back();
        } else {
          groups_.push_back(l.tok[1]);
        }
      } else if (k == "i") {
        if (l.tok.size() < 2) fail(l, "missing file name");
        fs::path f = fs::path(paths_.back()).parent_path() / l.tok[1];
        glm::dmat4 m = xform(l, 2, l.tok.size());
        std::string text;
        try {
          text = readInputFile(f.string(), "included MGF file", limits::kMaxMgfBytes);
        } catch (const InputError& err) {
          fail(l, std::string("cannot open included file ") + err.what());
        }
        readText(std::move(text), f.string(), m);
      } else if (k == "v") {
        context(l, vertices_, unnamedVertex_, curVertex_, "vertex");
      } else if (k == "p" || k == "n") {
        arity(l, 3, 3);
        Vec3 v(bounded(l, 1, limits::kCoordinate), bounded(l, 2, limits::kCoordinate), bounded(l, 3, limits::kCoordinate));
        (k == "p" ? vertex().p : vertex().n) = v;
      } else if (k == "c" || k == "cxy" || k == "cspec" || k == "cct" || k == "cmix") {
        colourEntity(l);
      } else if (k == "m" || k == "sides" || k == "rd" || k == "td" || k == "ed" || k == "rs" || k == "ts") {
        materialEntity(l);
      } else if (k == "ir" || k == "ies") {
        ++ignored_;
      } else if (k == "f" || k == "sph" || k == "cyl" || k == "cone" || k == "ring" || k == "torus" || k == "prism") {
        geometry(l);
      } else {
        fail(l, "unknown entity (MGF 1.1 entities: # o xf i ies c cxy cspec cct cmix m sides rd td ed rs ts ir v p n "
                "f sph cyl cone prism ring torus)");
      }
    }
  }
  std::size_t depthFloor() const { return files_.size(); }  // each file's own xf sits at its base

  /// The line of the "xf" that closes the context opened at line i (e if none before e).
  static std::size_t closing(const std::vector<Line>& lines, std::size_t i, std::size_t e) {
    std::size_t j = i + 1;
    for (int open = 1; j < e; ++j) {
      if (lines[j].tok[0] != "xf") continue;
      open += lines[j].tok.size() == 1 ? -1 : 1;
      if (open == 0) break;
    }
    return j;
  }
  /// Lines that [b, e) evaluates, arrays multiplied out, saturating just above the work limit.
  static std::uint64_t cost(const std::vector<Line>& lines, std::size_t b, std::size_t e) {
    const std::uint64_t cap = limits::kMaxMgfWork + 1;
    std::uint64_t c = 0;
    for (std::size_t i = b; i < e && c < cap; ++i) {
      ++c;
      const Line& l = lines[i];
      auto arr = std::find(l.tok.begin(), l.tok.end(), "-a");
      if (l.tok[0] != "xf" || arr == l.tok.end() || arr + 1 == l.tok.end()) continue;
      std::size_t j = closing(lines, i, e);
      double n = std::strtod((arr + 1)->c_str(), nullptr);
      n = std::isfinite(n) ? std::clamp(n, 1.0, double(cap)) : 1.0;  // run() refuses bad counts itself
      c += std::min<std::uint64_t>(cap, std::uint64_t(n) * cost(lines, i + 1, std::min(j, e)));
      i = j;
    }
    return std::min(c, cap);
  }

  // ---- vertices ---------------------------------------------------------------------------------
  /// The grammar v, c and m share: "kind" alone resets the unnamed context, "kind id" selects a
  /// defined one, "kind id = [template]" (re)defines one, from the template or from scratch.
  enum class Context { Reset, Selected, Defined };
  template <class T>
  Context context(const Line& l, std::map<std::string, T>& named, T& unnamed, std::string& current, const char* what) {
    if (l.tok.size() == 1) {
      current.clear();
      unnamed = T{};
      return Context::Reset;
    }
    const std::string& id = l.tok[1];
    if (l.tok.size() == 2) {
      if (!named.count(id)) fail(l, std::string("undefined ") + what + " " + echo(id));
      current = id;
      return Context::Selected;
    }
    if (l.tok[2] != "=" || l.tok.size() > 4) fail(l, "expected: " + l.tok[0] + " id [= [template]]");
    T v{};
    if (l.tok.size() == 4) {
      auto it = named.find(l.tok[3]);
      if (it == named.end()) fail(l, std::string("undefined template ") + what + " " + echo(l.tok[3]));
      v = it->second;
    }
    named[id] = v;
    current = id;
    return Context::Defined;
  }

  Vertex& vertex() { return curVertex_.empty() ? unnamedVertex_ : vertices_[curVertex_]; }
  const Vertex& named(const Line& l, std::size_t i) const {
    if (i >= l.tok.size()) fail(l, "missing vertex argument");
    auto it = vertices_.find(l.tok[i]);
    if (it == vertices_.end()) fail(l, "undefined vertex " + echo(l.tok[i]));
    return it->second;
  }

  // ---- colours ----------------------------------------------------------------------------------
  Colour& colour() { return curColour_.empty() ? unnamedColour_ : colours_[curColour_]; }
  void colourEntity(const Line& l) {
    const std::string& k = l.tok[0];
    if (k == "c") {
      context(l, colours_, unnamedColour_, curColour_, "colour");
      return;
    }
    Colour c = colour();
    if (k == "cxy") {
      arity(l, 2, 2);
      c.x = num(l, 1), c.y = num(l, 2);
      if (!(c.x >= 0.0 && c.y >= kMinChromaY && c.x + c.y <= 1.0))
        fail(l, "chromaticity outside the CIE triangle (x >= 0, y >= 0.001, x + y <= 1)");
    } else if (k == "cct") {
      arity(l, 1, 1);
      c = planckian(l, num(l, 1));
    } else if (k == "cmix") {
      if (l.tok.size() < 3 || (l.tok.size() - 1) % 2 != 0) fail(l, "expected: cmix w1 c1 w2 c2 ...");
      double X = 0, Y = 0, Z = 0;
      for (std::size_t i = 1; i + 1 < l.tok.size(); i += 2) {
        double w = bounded(l, i, limits::Range{"weight", 0.0, 1e30});
        auto it = colours_.find(l.tok[i + 1]);
        if (it == colours_.end()) fail(l, "undefined colour " + echo(l.tok[i + 1]));
        const Colour& m = it->second;
        X += w * m.x / m.y, Y += w, Z += w * (1.0 - m.x - m.y) / m.y;
      }
      if (!(X + Y + Z > 0.0) || !std::isfinite(X + Y + Z)) fail(l, "weights sum to nothing");
      c.x = X / (X + Y + Z), c.y = Y / (X + Y + Z);
      if (!(c.y >= kMinChromaY)) fail(l, "the mixture's chromaticity y is below 0.001");
    } else {  // cspec l_min l_max v1 v2 ...: a relative spectrum, equally spaced samples
      if (l.tok.size() < 5) fail(l, "expected: cspec l_min l_max v1 v2 ...");
      double lo = num(l, 1), hi = num(l, 2);
      if (!(lo >= 300.0 && hi > lo && hi <= 900.0)) fail(l, "wavelength range outside 300-900 nm or empty");
      std::vector<double> v;
      for (std::size_t i = 3; i < l.tok.size(); ++i) {
        v.push_back(bounded(l, i, limits::Range{"spectral value", 0.0, 1e30}));
      }
      Vec3 XYZ = spectrumToXyz(lo, hi, v);
      double sum = XYZ.x + XYZ.y + XYZ.z;
      if (!(sum > 0.0) || !(XYZ.y > 0.0) || !std::isfinite(sum)) fail(l, "the spectrum has no visible energy");
      c.x = XYZ.x / sum, c.y = XYZ.y / sum;
      if (!(c.y >= kMinChromaY)) fail(l, "the spectrum's chromaticity y is below 0.001");
      ++spectra_;
    }
    colour() = c;
  }
  /// CIE XYZ of a sampled spectrum (linear between samples, 1 nm steps), with the CIE 1931
  /// matching functions in the multi-lobe Gaussian fit of Wyman, Sloan and Shirley (JCGT 2013),
  /// accurate to a few per cent of the tables: ample for a colour's chromaticity.
  static Vec3 spectrumToXyz(double lo, double hi, const std::vector<double>& v) {
    auto g = [](double l, double mu, double s1, double s2) {
      double t = (l - mu) / (l < mu ? s1 : s2);
      return std::exp(-0.5 * t * t);
    };
    Vec3 sum(0.0);
    for (double l = std::ceil(lo); l <= hi; l += 1.0) {
      double f = v.size() == 1 ? 0.0 : (l - lo) / (hi - lo) * double(v.size() - 1);
      std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(f));
      double w = f - double(i), s = i + 1 < v.size() ? (1.0 - w) * v[i] + w * v[i + 1] : v[i];
      double x = 1.056 * g(l, 599.8, 37.9, 31.0) + 0.362 * g(l, 442.0, 16.0, 26.7) - 0.065 * g(l, 501.1, 20.4, 26.2);
      double y = 0.821 * g(l, 568.8, 46.9, 40.5) + 0.286 * g(l, 530.9, 16.3, 31.1);
      double z = 1.217 * g(l, 437.0, 11.8, 36.0) + 0.681 * g(l, 459.0, 26.0, 13.8);
      sum += s * Vec3(x, y, z);
    }
    return sum;
  }
  Colour planckian(const Line& l, double T) const {
    // Kim et al. (2002) cubic fit of the Planckian locus, 1667 K to 25000 K.
    if (!(T >= 1667.0 && T <= 25000.0)) fail(l, "colour temperature outside 1667-25000 K");
    double t = 1e3 / T, x;
    if (T <= 4000.0)
      x = -0.2661239 * t * t * t - 0.2343589 * t * t + 0.8776956 * t + 0.179910;
    else
      x = -3.0258469 * t * t * t + 2.1070379 * t * t + 0.2226347 * t + 0.240390;
    double y;
    if (T <= 2222.0)
      y = -1.1063814 * x * x * x - 1.34811020 * x * x + 2.18555832 * x - 0.20219683;
    else if (T <= 4000.0)
      y = -0.9549476 * x * x * x - 1.37418593 * x * x + 2.09137015 * x - 0.16748867;
    else
      y = 3.0817580 * x * x * x - 5.87338670 * x * x + 3.75112997 * x - 0.37001483;
    return {x, y};
  }

  // ---- materials ----------------------------------------------------------------------------------
  MgfMaterial& material() { return curMaterial_.empty() ? unnamedMaterial_ : materials_[curMaterial_]; }
  void materialEntity(const Line& l) {
    const std::string& k = l.tok[0];
    if (k == "m") {
      // Versions tell snapshot() when a material changed; a redefinition continues the count.
      int previous = l.tok.size() > 1 && materials_.count(l.tok[1]) ? materials_[l.tok[1]].version : -1;
      Context c = context(l, materials_, unnamedMaterial_, curMaterial_, "material");
      if (c == Context::Reset) unnamedMaterial_.version = ++unnamedVersions_;
      if (c == Context::Defined) materials_[curMaterial_].version = previous + 1;
      return;
    }
    MgfMaterial& m = material();
    ++m.version;
    auto fraction = [&](std::size_t i) {
      double v = num(l, i);
      if (v < 0.0 || v > 1.0) fail(l, "must be in [0, 1] (a negative or energy-gaining value is not physical)");
      return v;
    };
    if (k == "sides") {
      arity(l, 1, 1);
      double s = num(l, 1);
      if (s != 1.0 && s != 2.0) fail(l, "must be 1 or 2");
      m.sides = static_cast<int>(s);
    } else if (k == "rd") {
      arity(l, 1, 1);
      m.rd = fraction(1), m.cd = colour();
    } else if (k == "td") {
      arity(l, 1, 1);
      m.td = fraction(1), m.ctd = colour();
    } else if (k == "ed") {
      arity(l, 1, 1);
      // ed is luminous exitance, lm/m^2: the limit is the radiance limit for white light.
      m.ed = bounded(l, 1, limits::Range{"ed", 0.0, limits::kEmission.hi * kWhiteEfficacy * kPi}), m.ced = colour();
    } else if (k == "rs") {
      arity(l, 2, 2);
      m.rs = fraction(1), m.rsAlpha = bounded(l, 2, limits::Range{"roughness", 0.0, 1e6}), m.crs = colour();
    } else {  // ts
      arity(l, 2, 2);
      m.ts = fraction(1), m.tsAlpha = bounded(l, 2, limits::Range{"roughness", 0.0, 1e6}), m.cts = colour();
    }
  }
  /// The scene material for the current MGF material, made on first use of each version.
  std::string snapshot(const Line& l) {
    const std::string name = curMaterial_.empty() ? "(unnamed)" : curMaterial_;
    const MgfMaterial& m = material();
    const std::string base = stem() + ":" + name;
    auto cached = snapshots_.find({base, m.version});
    if (cached != snapshots_.end()) return cached->second;
    Material out;
    bool clipped = false;
    auto rgb = [&](const Colour& c, double Y) {
      Vec3 raw = cieToRgbUnclipped(c.x, c.y, Y);
      clipped = clipped || glm::min(raw.x, glm::min(raw.y, raw.z)) < -1e-9 * maxComponent(glm::abs(raw));
      return glm::max(raw, Vec3(0.0));
    };
    // A total above 1 gains energy. Classic files have such materials (cube.mgf: rd 0.9 + rs 0.2)
    // and other radiosity programs scale them down with a warning; so do we, and say so.
    double total = m.rd + m.td + m.rs + m.ts, k = 1.0;
    if (total > 1.0) {
      k = 1.0 / total;
      gaining_.insert(name + " (" + fmt(total) + ")");
    }
    out.diffuse = rgb(m.cd, k * m.rd);
    out.specular = rgb(m.crs, k * m.rs);
    out.emission = rgb(m.ced, m.ed) / (kWhiteEfficacy * kPi);
    if (m.rs > 0.0) {
      if (m.rsAlpha <= 0.0) {
        out.exponent = kMaxExponent;
        mirrors_.insert(name);
      } else {
        // Matches the width of a Gaussian (Beckmann) lobe of roughness alpha: n = 2 / alpha^2 - 2.
        out.exponent = std::clamp(2.0 / (m.rsAlpha * m.rsAlpha) - 2.0, 0.0, kMaxExponent);
      }
    }
    double worst = maxComponent(out.diffuse + out.specular);
    if (worst > 1.0) {
      out.diffuse /= worst, out.specular /= worst;
      scaled_.insert(name);
    }
    // Colour conversion of a saturated chromaticity can exceed the luminance it started from: the
    // material that results must still be finite and inside the limits table.
    for (int c = 0; c < 3; ++c) {
      if (!limits::within(out.emission[c], limits::kEmission))
        fail(l, "material " + echo(name) + ": emitted radiance " + fmt(out.emission[c]) + " outside " + limits::kEmission.text());
      if (!std::isfinite(out.diffuse[c]) || !std::isfinite(out.specular[c])) fail(l, "material " + echo(name) + ": non-finite colour");
    }
    if (clipped) clipped_.insert(name);
    if (m.td + m.ts > 0.0) {
      transmissive_.insert(name);
      maxTransmitted_ = std::max(maxTransmitted_, m.td + m.ts);
    }
    // Files redefine materials with the same values over and over: one scene material per distinct
    // definition, the second one named "name~2", and so on.
    std::vector<std::string>& variants = variants_[base];
    std::string key;
    for (const std::string& v : variants) {
      const Material& e = scene_.materials[scene_.materialIndex.at(v)];
      if (e.diffuse == out.diffuse && e.specular == out.specular && e.exponent == out.exponent && e.emission == out.emission)
        key = v;
    }
    if (key.empty()) {
      key = variants.empty() ? base : base + "~" + std::to_string(variants.size() + 1);
      out.name = key;
      variants.push_back(key);
      scene_.materialIndex[key] = static_cast<std::uint32_t>(scene_.materials.size());
      scene_.materials.push_back(out);
    }
    snapshots_[{base, m.version}] = key;
    return key;
  }
  std::string stem() const { return fs::path(paths_.front()).stem().string(); }

  // ---- geometry -------------------------------------------------------------------------------------
  Object start(const Line& l, PrimitiveType t) {
    Object o;
    o.type = t;
    o.where = where_ + paths_.back() + ": line " + std::to_string(l.number);
    o.material = snapshot(l);
    o.transform.explicitMatrix = current();
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite((*o.transform.explicitMatrix)[c][r])) fail(l, "the transform overflows");
    for (const auto& g : groups_) o.group += (o.group.empty() ? "" : "/") + g;
    return o;
  }
  /// Surfaces are one-sided in the core (front by MGF's right-hand rule). A two-sided MGF surface
  /// (sides 2, the default) is kept one-sided, as RenderPark does by default: a back-to-back copy
  /// would coincide with it, and rays cannot tell coincident faces apart.
  void add(const Line& l, const Object& o, bool open) {
    if (open && material().sides == 2) ++twoSided_;
    push(l, o);
  }
  /// Every object the reader makes goes through here: the count is bounded.
  void push(const Line& l, const Object& o) {
    if (scene_.objects.size() >= limits::kMaxObjects)
      fail(l, "more than " + std::to_string(limits::kMaxObjects) + " objects (the documented limit)");
    work(l, 1);
    scene_.objects.push_back(o);
  }
  void geometry(const Line& l) {
    const std::string& k = l.tok[0];
    ++scene_.entityCounts["mgf " + k];
    if (k == "f") {
      if (l.tok.size() < 4) fail(l, "a face needs at least 3 vertices");
      if (l.tok.size() - 1 > limits::kMaxFaceVertices)
        fail(l, "a face of " + std::to_string(l.tok.size() - 1) + " vertices, more than the limit of " +
                    std::to_string(limits::kMaxFaceVertices));
      Object o = start(l, PrimitiveType::Polygon);
      for (std::size_t i = 1; i < l.tok.size(); ++i) o.points.push_back(named(l, i).p);
      add(l, o, true);
    } else if (k == "sph") {
      arity(l, 2, 2);
      Object o = start(l, PrimitiveType::Sphere);
      o.center = named(l, 1).p;
      double r = bounded(l, 2, limits::Range{"radius", -limits::kLength.hi, limits::kLength.hi});
      if (r == 0.0) fail(l, "zero radius");
      o.radius = std::abs(r), o.inward = r < 0.0;
      add(l, o, false);
    } else if (k == "cyl" || k == "cone") {
      bool cyl = k == "cyl";
      arity(l, cyl ? 3 : 4, cyl ? 3 : 4);
      Vec3 a = named(l, 1).p, b = named(l, 3).p;
      const limits::Range radius{"radius", -limits::kLength.hi, limits::kLength.hi};
      double r0 = bounded(l, 2, radius), r1 = cyl ? r0 : bounded(l, 4, radius);
      if (r0 == 0.0 && r1 == 0.0) fail(l, "both radii are zero");
      if (r0 * r1 < 0.0) fail(l, "radii of opposite signs");
      if (glm::length(b - a) == 0.0) fail(l, "the two end vertices coincide");
      Object o = start(l, cyl ? PrimitiveType::Cylinder : PrimitiveType::Cone);
      o.base = a, o.axis = glm::normalize(b - a), o.height = glm::length(b - a);
      o.radius = std::abs(r0), o.radius2 = std::abs(r1), o.inward = r0 < 0.0 || r1 < 0.0;
      add(l, o, true);
    } else if (k == "ring") {
      arity(l, 3, 3);
      const Vertex& c = named(l, 1);
      if (glm::length(c.n) == 0.0) fail(l, "the centre vertex needs a normal (n)");
      const limits::Range radius{"radius", -limits::kLength.hi, limits::kLength.hi};
      double r0 = std::abs(bounded(l, 2, radius)), r1 = std::abs(bounded(l, 3, radius));
      if (r0 == r1) fail(l, "equal radii: zero area");
      Object o = start(l, PrimitiveType::Ring);
      o.center = c.p, o.normal = glm::normalize(c.n), o.radius = std::min(r0, r1), o.radius2 = std::max(r0, r1);
      add(l, o, true);
    } else if (k == "torus") {
      arity(l, 3, 3);
      torus(l);
    } else {
      prism(l);
    }
  }
  /// A torus between inner radius r0 and outer radius r1 about the centre's normal, as quads
  /// (the core has no torus primitive); negative radii face inward.
  void torus(const Line& l) {
    const Vertex& c = named(l, 1);
    if (glm::length(c.n) == 0.0) fail(l, "the centre vertex needs a normal (n)");
    const limits::Range radius{"radius", -limits::kLength.hi, limits::kLength.hi};
    double a = bounded(l, 2, radius), b = bounded(l, 3, radius);
    if (a * b < 0.0) fail(l, "radii of opposite signs");
    double r0 = std::abs(a), r1 = std::abs(b);
    if (r0 >= r1) fail(l, "the inner radius must be smaller than the outer one");
    bool inward = a < 0.0 || b < 0.0;
    Vec3 w = glm::normalize(c.n), t = std::abs(w.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
    Vec3 u = glm::normalize(glm::cross(t, w)), v = glm::cross(w, u);
    double major = 0.5 * (r0 + r1), minor = 0.5 * (r1 - r0);
    const int seg = std::max(8, scene_.settings.tessellation), sub = std::max(4, seg / 2);
    // Scaled about the centre so that the quads keep the torus's area 4 pi^2 R r, as the tessellator
    // keeps every round primitive's (tessellate.cpp): the quads between two tube angles are a band.
    double area = 0.0;
    for (int j = 0; j < sub; ++j) {
      const double q0 = 2.0 * kPi * j / sub, q1 = 2.0 * kPi * (j + 1) / sub;
      area += polygonBandArea(major + minor * std::cos(q0), minor * std::sin(q0), major + minor * std::cos(q1),
                              minor * std::sin(q1), seg);
    }
    const double k = std::sqrt(4.0 * kPi * kPi * major * minor / area);
    auto at = [&](int i, int j) {
      double p = 2.0 * kPi * i / seg, q = 2.0 * kPi * j / sub;
      Vec3 radial = std::cos(p) * u + std::sin(p) * v;
      return c.p + k * ((major + minor * std::cos(q)) * radial + minor * std::sin(q) * w);
    };
    for (int i = 0; i < seg; ++i)
      for (int j = 0; j < sub; ++j) {
        Object o = start(l, PrimitiveType::Polygon);
        o.points = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
        if (inward) std::reverse(o.points.begin(), o.points.end());
        push(l, o);
      }
  }
  /// A closed prism: the polygon, its copy moved len along the polygon's normal, and the sides.
  void prism(const Line& l) {
    if (l.tok.size() < 5) fail(l, "expected: prism v1 v2 v3 ... len");
    if (l.tok.size() - 2 > limits::kMaxFaceVertices)
      fail(l, "a prism base of " + std::to_string(l.tok.size() - 2) + " vertices, more than the limit of " +
                  std::to_string(limits::kMaxFaceVertices));
    double len = bounded(l, l.tok.size() - 1, limits::Range{"length", -limits::kLength.hi, limits::kLength.hi});
    if (len == 0.0) fail(l, "zero length");
    std::vector<Vec3> base;
    for (std::size_t i = 1; i + 1 < l.tok.size(); ++i) base.push_back(named(l, i).p);
    Vec3 n(0.0);
    for (std::size_t i = 0; i < base.size(); ++i) n += glm::cross(base[i], base[(i + 1) % base.size()]);
    if (glm::length(n) == 0.0) fail(l, "the base polygon has zero area");
    Vec3 d = glm::normalize(n) * len;
    bool flip = len < 0.0;  // extruded against the normal: reverse every face to keep them outward
    auto emit = [&](std::vector<Vec3> pts) {
      if (flip) std::reverse(pts.begin(), pts.end());
      Object o = start(l, PrimitiveType::Polygon);
      o.points = std::move(pts);
      push(l, o);
    };
    std::vector<Vec3> top, bottom(base.rbegin(), base.rend());
    for (const Vec3& p : base) top.push_back(p + d);
    emit(bottom);
    emit(top);
    for (std::size_t i = 0; i < base.size(); ++i) {
      std::size_t j = (i + 1) % base.size();
      emit({base[i], base[j], base[j] + d, base[i] + d});
    }
  }

  Scene& scene_;
  glm::dmat4 base_;
  std::string where_;
  std::vector<std::string> files_, paths_, groups_;
  std::vector<glm::dmat4> xf_;
  std::map<std::string, Vertex> vertices_;
  Vertex unnamedVertex_;
  std::string curVertex_;
  std::map<std::string, Colour> colours_;
  Colour unnamedColour_;
  std::string curColour_;
  std::map<std::string, MgfMaterial> materials_;
  MgfMaterial unnamedMaterial_;
  std::string curMaterial_;
  int unnamedVersions_ = 0;
  std::set<std::string> transmissive_, mirrors_, scaled_, clipped_, gaining_;
  std::map<std::pair<std::string, int>, std::string> snapshots_;  // (material, version) -> scene material
  std::map<std::string, std::vector<std::string>> variants_;      // distinct definitions per material
  double maxTransmitted_ = 0.0;
  std::uint64_t work_ = 0;
  std::size_t spectra_ = 0, ignored_ = 0, twoSided_ = 0;
};

}  // namespace

Vec3 cieToRgbUnclipped(double x, double y, double Y) {
  if (Y == 0.0) return Vec3(0.0);
  // XYZ -> linear RGB for Rec. 709 primaries and the equal-energy white E, built once.
  static const glm::dmat3 toRgb = [] {
    auto col = [](double px, double py) { return Vec3(px / py, 1.0, (1.0 - px - py) / py); };
    glm::dmat3 P(col(0.64, 0.33), col(0.30, 0.60), col(0.15, 0.06));
    Vec3 s = glm::inverse(P) * Vec3(1.0, 1.0, 1.0);  // white E: X = Y = Z
    glm::dmat3 M(P[0] * s.x, P[1] * s.y, P[2] * s.z);
    return glm::inverse(M);
  }();
  return toRgb * Vec3(x / y * Y, Y, (1.0 - x - y) / y * Y);
}

Rgb cieToRgb(double x, double y, double Y) { return glm::max(cieToRgbUnclipped(x, y, Y), Vec3(0.0)); }

void readMgf(const std::string& path, Scene& scene, const glm::dmat4& xf, const std::string& where) {
  MgfReader r(scene, xf, where);
  r.readFile(path, glm::dmat4(1.0));
  r.finish();
}

void parseMgf(const std::string& text, const std::string& path, Scene& scene) {
  MgfReader r(scene, glm::dmat4(1.0), "");
  r.readText(text, path, glm::dmat4(1.0));
  r.finish();
}

Scene loadMgfScene(const std::string& path) {
  Scene s;
  s.path = path;
  s.name = fs::path(path).stem().string();
  readMgf(path, s);
  if (s.objects.empty()) throw InputError(path + ": no geometry");
  return s;
}

}  // namespace hr
