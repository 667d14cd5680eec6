// A leaf's brightest incident light for the display (see shown_light.h): which samples are kept, the
// cell mean of their lobes as the solve deposits them, and their reflection at a shown point.
#include <glossy/brdf.h>
#include <glossy/cell_rules.h>
#include <glossy/gauss_legendre.h>
#include <glossy/haar_lobes.h>
#include <glossy/lobe_level.h>
#include <glossy/phong_power.h>
#include <glossy/reflection.h>
#include <glossy/shown_light.h>
#include <glossy/sphere.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <tuple>
#include <unordered_map>

namespace glossy {

namespace {

bool usable(const hr::IncidentSample& s) {
  return hr::allFinite(s.irradiance) && hr::allFinite(s.toSender) && glm::length(s.toSender) > 0.0 &&
         glm::all(glm::greaterThanEqual(s.irradiance, Rgb(0.0))) && hr::luminance(s.irradiance) > 0.0 &&
         std::isfinite(s.distance) && std::isfinite(s.radius);
}

/// A host's shape for a flat sender, its axis laid into the sender's plane to rounding (the solution
/// file holds it to that); none when it is not finite or leans out of the plane.
hr::SenderRectangle shapeOf(const hr::IncidentSample& s, const glm::vec3& senderNormal) {
  const hr::SenderRectangle& r = s.senderShape;
  const Vec3 a(r.axis), n(senderNormal);
  if (senderNormal == glm::vec3(0.0f) || !hr::allFinite(a) || !std::isfinite(r.halfWidth) ||
      !(r.halfWidth >= 0.0f) || std::abs(glm::dot(a, n)) > 1e-3 * glm::length(a))
    return {};
  return {glm::vec3(a - glm::dot(a, n) * n), r.halfWidth};
}

bool brighter(const ShownLight::Sample& a, const ShownLight::Sample& b) {
  return hr::luminance(Rgb(a.irradiance)) > hr::luminance(Rgb(b.irradiance));
}

/// A flat piece's own area covariance in its plane (m^2): its rectangle's, else the disk of its
/// radius (IncidentSample::radius, a disk of spread2 (1 + c^2) about it, c the cosine at the sender).
/// So a group gets the rectangle of its moments even from shapeless pieces: they lie in one plane,
/// and the rectangle carries the foreshortening that a disk across the line of sight does not.
glm::dmat3 pieceMoments(const ShownLight::Sample& x) {
  const Vec3 n(x.senderNormal);
  if (x.senderShape.axis != glm::vec3(0.0f)) return hr::momentsOfRectangle(x.senderShape, n);
  const double c = glm::dot(n, Vec3(x.toSender));
  const double spread2 = double(x.radius) * double(x.radius) / (1.0 + c * c);
  return 0.5 * spread2 * (glm::dmat3(1.0) - glm::outerProduct(n, n));
}

/// Pieces alike but for their irradiance (one link's light in several shooting passes) made one: a
/// deposit is linear in the irradiance, so the sum deposits the same lobes, and a leaf's pieces stay
/// as many as the senders it sees, not the passes it took.
void mergeAlike(std::vector<ShownLight::Sample>& pieces) {
  auto key = [](const ShownLight::Sample& x) {
    const glm::vec3 &t = x.toSender, &f = x.from, &n = x.normal, &s = x.senderNormal, &a = x.senderShape.axis;
    return std::tuple(t.x, t.y, t.z, f.x, f.y, f.z, n.x, n.y, n.z, s.x, s.y, s.z, x.distance, x.radius, a.x,
                      a.y, a.z, x.senderShape.halfWidth);
  };
  std::stable_sort(pieces.begin(), pieces.end(),
                   [&](const ShownLight::Sample& a, const ShownLight::Sample& b) { return key(a) < key(b); });
  std::size_t n = 0;
  for (std::size_t k = 0; k < pieces.size(); ++k)
    if (n > 0 && key(pieces[n - 1]) == key(pieces[k])) pieces[n - 1].irradiance += pieces[k].irradiance;
    else pieces[n++] = pieces[k];
  pieces.resize(n);
}

/// Pieces of one flat sender within `reach` (radians) of a group's centre as the leaf sees them,
/// joined into one sample: their irradiance summed, about their luminance-weighted centre, with the
/// second moment of all of them across the line of sight (so the disk they make is as wide as the
/// pieces together) and in the sender's plane (the rectangle they make: a lamp's quarters, the
/// lamp). v comes brightest first; each piece goes into the group it fits nearest; only the
/// brightest kMaxPieces are looked at (grouping is quadratic in them). A group that would be
/// wider than `widest` times its distance (a shown sample's limit) keeps its pieces apart. A joined
/// sample's pieces (its members, or theirs where a member was joined before: ranges of `pool`) are
/// appended to `pool` as its range.
void joinPieces(std::vector<ShownLight::Sample>& v, std::vector<ShownLight::Sample>& pool, double reach,
                double widest) {
  struct Group {
    std::vector<std::size_t> pieces;  // the first, the brightest, names its leaf, plane and sender normal
    double weight = 0.0;              // luminance
    Rgb irradiance{0.0};              // W/m^2
    Vec3 sum{0.0};                    // luminance-weighted sums of the pieces' centres (m),
    glm::dmat3 outer{0.0};            // of their outer products (m^2)
    double own = 0.0;                 // and of their own spread across the line of sight, r^2 / 2 (m^2),
    glm::dmat3 ownMoments{0.0};       // and in the sender's plane (m^2)
    Vec3 toward{0.0};                 // unit, from the leaf to the group's centre
  };
  // The disk of a group's second moment across the line of sight from `from` (the centres' spread
  // about their mean, trace less the part along the line, and the pieces' own), as a host's radius
  // is: its radius (m), and the distance (m) and unit direction to its centre.
  auto disk = [](const Group& g, const Vec3& from, double& d, Vec3& w) {
    const Vec3 m = g.sum / g.weight, to = m - from;
    d = glm::length(to);
    w = d > 0.0 ? to / d : Vec3(0.0);
    const glm::dmat3 c = g.outer / g.weight - glm::outerProduct(m, m);
    const double across = c[0][0] + c[1][1] + c[2][2] - glm::dot(w, c * w);
    return std::sqrt(2.0 * (std::max(0.0, across) + g.own / g.weight));
  };
  std::vector<Group> groups;
  std::vector<ShownLight::Sample> out;
  auto centreOf = [](const ShownLight::Sample& x) { return Vec3(x.from) + double(x.distance) * Vec3(x.toSender); };
  const double cosReach = std::cos(reach);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const ShownLight::Sample& x = v[i];
    if (x.senderNormal == glm::vec3(0.0f) || !(x.distance > 0.0f) || i >= std::size_t(kMaxPieces)) {
      out.push_back(x);
      continue;
    }
    const Vec3 c = centreOf(x);
    Group* best = nullptr;
    double nearest = 0.0;  // the least angle to a group's centre, rad
    for (Group& g : groups) {
      // The direction first: a leaf's pieces spread over a wall make many groups, most of them far
      // off (the VISION-like glossy furnace spent a tenth of its solve in this loop).
      const double cosine = glm::dot(g.toward, Vec3(x.toSender));
      if (cosine < cosReach) continue;  // cheap rejection before the exact angle
      const ShownLight::Sample& f = v[g.pieces.front()];
      if (f.from != x.from || f.normal != x.normal || glm::dot(f.senderNormal, x.senderNormal) < 0.9999f) continue;
      if (std::abs(glm::dot(Vec3(f.senderNormal), c - centreOf(f))) > 1e-3 * double(x.distance)) continue;  // another plane
      const double past = std::atan2(glm::length(glm::cross(g.toward, Vec3(x.toSender))), cosine);
      if (past > reach) continue;
      if (!best || past < nearest) nearest = past, best = &g;
    }
    if (!best) {
      groups.emplace_back();
      best = &groups.back();
    }
    const double lum = hr::luminance(Rgb(x.irradiance));
    best->pieces.push_back(i);
    best->weight += lum;
    best->irradiance += Rgb(x.irradiance);
    best->sum += lum * c;
    best->outer += lum * glm::outerProduct(c, c);
    best->own += lum * 0.5 * double(x.radius) * double(x.radius);
    best->ownMoments += lum * pieceMoments(x);
    const Vec3 to = best->sum / best->weight - Vec3(x.from);
    const double len = glm::length(to);
    best->toward = len > 0.0 ? to / len : Vec3(x.toSender);
  }
  for (const Group& g : groups) {
    ShownLight::Sample x = v[g.pieces.front()];
    if (g.pieces.size() > 1) {
      double d = 0.0;
      Vec3 w(0.0);
      const double radius = disk(g, Vec3(x.from), d, w);
      if (!(d > 0.0) || !(radius <= widest * d)) {
        for (std::size_t k : g.pieces) out.push_back(v[k]);
        continue;
      }
      x.toSender = glm::vec3(w);
      x.distance = float(d);
      x.radius = float(radius);
      x.irradiance = glm::vec3(g.irradiance);
      const Vec3 m = g.sum / g.weight;
      const glm::dmat3 moments = g.outer / g.weight - glm::outerProduct(m, m) + g.ownMoments / g.weight;
      x.senderShape = hr::rectangleOfMoments(moments, Vec3(x.senderNormal), Vec3(x.senderShape.axis));
      // Its pieces as deposited, the members' own where they were joined before.
      std::vector<ShownLight::Sample> pieces;
      for (std::size_t k : g.pieces) {
        const ShownLight::Sample& y = v[k];
        if (y.pieces == 0) pieces.push_back(y);
        else pieces.insert(pieces.end(), pool.begin() + y.firstPiece, pool.begin() + y.firstPiece + y.pieces);
      }
      mergeAlike(pieces);
      x.firstPiece = std::uint32_t(pool.size());
      x.pieces = std::uint32_t(pieces.size());
      pool.insert(pool.end(), pieces.begin(), pieces.end());
    }
    out.push_back(x);
  }
  v = std::move(out);
}

/// Those that keep their share of the total, the brightest first, at most kShownSamples.
void keepBrightest(std::vector<ShownLight::Sample>& v, double total) {
  std::erase_if(v, [&](const ShownLight::Sample& x) { return !(hr::luminance(Rgb(x.irradiance)) >= kShownShare * total); });
  std::stable_sort(v.begin(), v.end(), brighter);
  if (v.size() > std::size_t(kShownSamples)) v.resize(std::size_t(kShownSamples));
}

double keptLight(const std::vector<ShownLight::Sample>& v) {
  double kept = 0.0;
  for (const ShownLight::Sample& x : v) kept += hr::luminance(Rgb(x.irradiance));
  return kept;
}

/// The samples a leaf keeps: its brightest, a flat sender's pieces joined only as far as it takes to
/// keep their light. A finer solution splits a lamp into more pieces, each a smaller share of the
/// leaf's light: kept one by one, floor_gloss's lamp at eps 2e-4 reached its sphere's leaves in pieces
/// under kShownShare or beyond kShownSamples, and the highlight's peak lost 10 % to the cell means
/// (the image 0.35 from the reference against 0.06 at eps 5e-4). Joined always at a quarter of the
/// lobe's width, the pieces of the coarser solution lost their layout (0.062 -> 0.066): so the
/// narrowest of kMergeWidths unless a wider one keeps more than one share more light. Per join: a
/// leaf joined one sample at a time (Radiance Clustering) never widens, since one piece is under a
/// share, and keeps what it kept before (docs/glossy.md, "A lamp in many pieces"). `pool` holds the
/// pieces v's joined samples name; it comes back holding the kept samples' pieces alone.
void keepJoined(std::vector<ShownLight::Sample>& v, std::vector<ShownLight::Sample>& pool, double total,
                double exponent) {
  const double width = lobeWidth(exponent), widest = kShownWidth * width;
  std::stable_sort(v.begin(), v.end(), brighter);  // once, for every width's join
  // No join keeps more than all of it: once the one taken is within a share of that, a wider one
  // could not be taken, and is not tried (most leaves stop at the first).
  const double all = keptLight(v);
  // Every width's joins append their groups' pieces to the one pool, whose earlier entries stay as
  // they are; the kept samples' pieces are copied out at the end.
  std::vector<ShownLight::Sample> best;
  double bestKept = -1.0;
  for (const double w : kMergeWidths) {
    if (all <= bestKept + kShownShare * total) break;
    std::vector<ShownLight::Sample> t = v;
    joinPieces(t, pool, w * width, widest);
    keepBrightest(t, total);
    const double kept = keptLight(t);
    if (kept > bestKept + kShownShare * total) best = std::move(t), bestKept = kept;
  }
  std::size_t count = 0;
  for (const ShownLight::Sample& x : best) count += x.pieces;
  std::vector<ShownLight::Sample> pieces;
  pieces.reserve(count);
  for (ShownLight::Sample& x : best) {
    if (x.pieces == 0) continue;
    const std::uint32_t first = std::uint32_t(pieces.size());
    pieces.insert(pieces.end(), pool.begin() + x.firstPiece, pool.begin() + x.firstPiece + x.pieces);
    x.firstPiece = first;
  }
  pool = std::move(pieces);
  v = std::move(best);
}

// Directions a source's disk is integrated over at the display: enough that a disk several lobe
// widths across shows its shape (each direction is one cos^n evaluation per shown point).
constexpr int kDiskPoints = 32;

/// The kDiskPoints' sunflower steps, computed once.
const std::array<SunflowerStep, kDiskPoints>& diskPoints() {
  static const std::array<SunflowerStep, kDiskPoints> table = [] {
    std::array<SunflowerStep, kDiskPoints> t{};
    for (int j = 0; j < kDiskPoints; ++j) t[std::size_t(j)] = sunflowerStep(j, kDiskPoints);
    return t;
  }();
  return table;
}

/// The lobe cos^n(alpha) about a direction at cos(alpha) = a from the mirror direction, averaged over a
/// disk of directions of squared angular radius rho2 about it, to second order: times
/// 1 + (rho2 / 8) Laplacian / value = 1 + (rho2 / 8)(n (n - 1) tan^2 - 2 n). At its centre alone a
/// small source reads the peak of a curved lobe: floor_gloss's lamp, in 16 parts each under a sixth
/// of the lobe's width, shone 1.2 % bright at its highlight (ShownLight.ASmallSourcesHighlightIsTheLobesMeanOverItsDisk).
/// (Per point of a wider source's disk it changed nothing: their error, 0.4-1.2 % of the peak at
/// 0.25-0.75 lobe widths, is not the points' own curvature.)
double lobeOverDisk(double a, const PhongPower& power, double rho2) {
  a = std::min(a, 1.0);
  if (!(a > 0.0)) return 0.0;
  const double n = power.exponent(), tan2 = (1.0 - a * a) / (a * a);
  return power(a) * std::max(0.0, 1.0 + rho2 / 8.0 * (n * (n - 1.0) * tan2 - 2.0 * n));
}

// Gauss-Legendre points per axis of a shown source's rectangle: a source is at most kShownWidth lobe
// widths across, over which the lobe falls smoothly (ShownLight.ARectangularSourcesHighlightIsItsShape).
constexpr int kRectanglePoints = 6;

/// Whether a source whose directions lie within `spread` (rad) of unit wi sends nothing into toEye's
/// lobe at a point of normal n: their mirrors lie within spread of wi's, and the nearest of them to
/// toEye is still beyond `reach` (the cosine below which cos^n is dropped).
bool beyondLobe(const Vec3& wi, const Vec3& n, const Vec3& toEye, double spread, double reach) {
  const double a0 = std::clamp(glm::dot(mirror(wi, n), toEye), -1.0, 1.0);
  return a0 < std::cos(spread) && a0 * std::cos(spread) + std::sqrt(1.0 - a0 * a0) * std::sin(spread) < reach;
}

/// The lobe cos^n about toEye's mirror, averaged over a flat rectangle (shape r, unit normal sn) whose
/// centre lies at `to` (m, d = |to| > 0, wi = to / d) from a point of normal n: each point weighted by
/// the irradiance it sends there, the cosines at both ends over the squared distance. 0 when none of
/// it is above the point's horizon, or when all of it lies beyond the lobe's reach.
double lobeOverRectangle(const Vec3& to, double d, const Vec3& wi, const hr::SenderRectangle& r,
                         const Vec3& sn, const Vec3& n, const Vec3& toEye, const PhongPower& power,
                         double reach) {
  static const auto rule = [] {
    std::pair<std::vector<double>, std::vector<double>> t;
    gaussLegendre(kRectanglePoints, t.first, t.second);
    return t;
  }();
  const Vec3 a(r.axis), b = hr::rectangleSide(r.axis, sn) * double(r.halfWidth);
  // Every point lies within asin(s / d) of wi, s = |a| + |b| at least its half-diagonal; a rectangle
  // for which s passes d may lie anywhere about the point, and is not culled.
  const double across = glm::length(a) + glm::length(b);
  if (across < d && beyondLobe(wi, n, toEye, std::asin(across / d), reach)) return 0.0;
  double weights = 0.0, lit = 0.0;
  for (int i = 0; i < kRectanglePoints; ++i)
    for (int j = 0; j < kRectanglePoints; ++j) {
      const Vec3 q = to + rule.first[std::size_t(i)] * a + rule.first[std::size_t(j)] * b;
      const double q2 = glm::dot(q, q);
      if (!(q2 > 0.0)) continue;
      const Vec3 w = q / std::sqrt(q2);
      const double cx = glm::dot(n, w), cs = -glm::dot(sn, w);
      if (!(cx > 0.0) || !(cs > 0.0)) continue;
      const double k = rule.second[std::size_t(i)] * rule.second[std::size_t(j)] * cx * cs / q2;
      weights += k;
      lit += k * power(glm::dot(mirror(w, n), toEye));
    }
  return weights > 0.0 ? lit / weights : 0.0;
}

}  // namespace

std::shared_ptr<const ShownLight> keepShown(std::span<const hr::IncidentSample> samples, const Vec3& from,
                                            const Vec3& normal, const Rgb& specular, double exponent,
                                            int level, int senderPoints) {
  double total = 0.0;
  for (const hr::IncidentSample& s : samples)
    if (usable(s) && glm::dot(s.toSender, normal) > 0.0) total += hr::luminance(s.irradiance);
  if (!(total > 0.0)) return nullptr;
  auto out = std::make_shared<ShownLight>();
  const double widest = kShownWidth * lobeWidth(exponent);
  for (const hr::IncidentSample& s : samples)
    if (usable(s) && glm::dot(s.toSender, normal) > 0.0 && hr::luminance(s.irradiance) >= kPieceShare * total &&
        !(s.distance > 0.0 && s.radius > widest * s.distance)) {
      const float len = glm::length(s.senderNormal);
      const bool flat = std::isfinite(len) && std::abs(len - 1.0f) < 1e-3f;
      const glm::vec3 senderNormal = flat ? s.senderNormal / len : glm::vec3(0.0f);
      out->samples.push_back({glm::vec3(glm::normalize(s.toSender)), glm::vec3(s.irradiance), glm::vec3(from),
                              glm::vec3(normal), senderNormal, float(s.distance), float(s.radius),
                              shapeOf(s, senderNormal)});
    }
  keepJoined(out->samples, out->deposited, total, exponent);
  if (out->samples.empty()) return nullptr;
  out->total = total;
  out->specular = specular;
  out->exponent = exponent;
  out->level = level;
  out->senderPoints = senderPoints;
  return out;
}

std::shared_ptr<const ShownLight> joinShown(const std::shared_ptr<const ShownLight>& a,
                                            const std::shared_ptr<const ShownLight>& b) {
  if (!a || a->samples.empty()) return b;
  if (!b || b->samples.empty()) return a;
  auto out = std::make_shared<ShownLight>(*b);
  out->samples = a->samples;
  out->samples.insert(out->samples.end(), b->samples.begin(), b->samples.end());
  out->deposited = a->deposited;
  out->deposited.insert(out->deposited.end(), b->deposited.begin(), b->deposited.end());
  for (std::size_t k = a->samples.size(); k < out->samples.size(); ++k)
    if (out->samples[k].pieces > 0) out->samples[k].firstPiece += std::uint32_t(a->deposited.size());
  out->total = a->total + b->total;
  keepJoined(out->samples, out->deposited, out->total, out->exponent);
  // Every sample may lose its share of the joint total (many passes of equal light): none is kept.
  if (out->samples.empty()) return nullptr;
  return out;
}

namespace {

Rgb cellMeanNow(const ShownLight& s, const Frame& frame, double area, int level, std::uint64_t index, double omega) {
  if (!(omega > 0.0)) return Rgb(0.0);
  // Each sample's lobes as its leaf deposited them (about that leaf's normal), turned into this frame.
  LobeSet lobes;
  lobes.exponent = s.exponent;
  ReflectCounts rc;
  auto add = [&](const ShownLight::Sample& x) {
    const Frame own = Frame::around(Vec3(x.normal));
    const hr::IncidentSample in = x.in();
    const LobeSet one = makeLobes({&in, 1}, own, Vec3(x.normal), area, s.specular, s.exponent, 0.0, rc, s.senderPoints, cellSize(s.level));
    for (const LobeSample& l : one.samples) lobes.samples.push_back({frame.toLocal(own.toWorld(l.mirror)), l.weight, false});
  };
  // A joined sample's pieces, as the solve deposited them.
  for (const ShownLight::Sample& x : s.samples)
    if (x.pieces == 0) add(x);
    else
      for (const ShownLight::Sample& p : s.piecesOf(x)) add(p);
  // At the leaf's own level and summed up to the cell read, as the stored tree's means were: the
  // same quadrature, so the two means differ by rounding alone. A cell finer than that level (a
  // re-projected child's) gets the mean of the cell of that level holding it.
  std::uint64_t evaluations = 0;
  if (level > s.level) {
    const std::uint64_t holder = index >> (2 * (level - s.level));
    const double whole = UpperCells::cell(s.level, holder).solidAngle();
    return whole > 0.0 ? integrateLobesInCell(lobes, s.level, s.level, holder, evaluations) / whole : Rgb(0.0);
  }
  return integrateLobesInCell(lobes, s.level, level, index, evaluations) / omega;
}

/// shownCellMean's memo: a still image asks it once per pixel sample of a shown leaf, for the few
/// cells the leaf's pixels see (glossy_sphere on the VISION-like host at --max-level 2: 10.5 s of
/// render, most of it these lobes made and integrated again per pixel). Keyed by the shown light's
/// identity and the cell, the leaf's frame and area checked on a hit (a shown light handed to
/// children serves leaves of other areas); per thread, so no lock; cleared when full.
struct CellMeanMemo {
  struct Key {
    std::uint64_t shown, index;
    int level;
    bool operator==(const Key&) const = default;
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return std::hash<std::uint64_t>()(k.shown * 0x9E3779B97F4A7C15ull ^ k.index * 0xC2B2AE3D27D4EB4Full ^ std::uint64_t(k.level));
    }
  };
  struct Entry {
    Frame frame;
    double area, omega;
    Rgb value;
  };
  static constexpr std::size_t kMaxEntries = std::size_t(1) << 12;
  std::unordered_map<Key, Entry, Hash> map;
};

bool sameFrame(const Frame& a, const Frame& b) { return a.u == b.u && a.v == b.v && a.n == b.n; }

}  // namespace

Rgb shownCellMean(const ShownLight& s, const Frame& frame, double area, int level, std::uint64_t index, double omega) {
  thread_local CellMeanMemo memo;
  const CellMeanMemo::Key key{s.identity.value(), index, level};
  if (auto it = memo.map.find(key); it != memo.map.end()) {
    const CellMeanMemo::Entry& e = it->second;
    if (e.area == area && e.omega == omega && sameFrame(e.frame, frame)) return e.value;
  }
  const Rgb value = cellMeanNow(s, frame, area, level, index, omega);
  if (memo.map.size() >= CellMeanMemo::kMaxEntries) memo.map.clear();
  memo.map.insert_or_assign(key, CellMeanMemo::Entry{frame, area, omega, value});
  return value;
}

std::uint64_t Identity::next() {
  static std::atomic<std::uint64_t> counter{0};
  return counter.fetch_add(1, std::memory_order_relaxed) + 1;
}

Rgb shownRadiance(const ShownLight& s, const Vec3& x, const Vec3& n, const Vec3& toEye) {
  const Rgb f = s.specular * ((s.exponent + 2.0) / (2.0 * kPi));
  const double width = lobeWidth(s.exponent);
  const PhongPower power(s.exponent);  // cos^n by squaring: std::pow per direction was most of what is left
  // The lobe's reach: below this cosine to its axis cos^n < 1e-15 (of its peak, f e), so a disk whose
  // reflection lies wholly outside it adds nothing an image keeps (float radiance has 24 bits). Most
  // of a shiny sphere's pixels see no highlight: evaluated there, the disks' directions were 95 % of
  // a glossy still's render (glossy_sphere on the VISION-like host at --max-level 2: 10.5 s to render
  // after a 1.0 s solve).
  const double reach = std::sqrt(power.cutoff());  // cos^n = 1e-15 there (the square root of its 1e-30)
  Rgb sum(0.0);
  for (const ShownLight::Sample& smp : s.samples) {
    // Re-aimed from x: the sender's centre where its distance is known, else the same direction.
    const hr::IncidentSample in = smp.in();
    Vec3 wi = in.toSender, to(0.0);  // to: from x to the sender's centre, m
    double d = 0.0;
    if (in.distance > 0.0) {
      to = Vec3(smp.from) + in.distance * in.toSender - x;
      d = glm::length(to);
      if (d > 0.0) wi = to / d;
    }
    const double cosX = glm::dot(n, wi), cosLeaf = glm::dot(Vec3(smp.normal), in.toSender);
    if (!(cosX > 0.0) || !(cosLeaf > 0.0)) continue;
    // The irradiance on x's tangent plane at x's distance, from the leaf's mean on its own plane;
    // held to a factor of 4 either way (a sender nearer than the leaf is wide).
    double scale = cosX / cosLeaf;
    if (d > 0.0) scale *= (in.distance / d) * (in.distance / d);
    // A flat sender is also foreshortened otherwise from x: floor_gloss's tilted lamp, 2 m from the
    // sphere, is 3 % brighter seen from a leaf 10 cm nearer its axis, and a highlight drawn from the
    // leaves around it moved with their layout (the VISION-like host's peak 1.9 % bright). Outside
    // the clamp, so that the light fades to nothing as x nears the sender's plane; held to 4 above
    // (a leaf that saw the sender edge-on). A Lambertian sender's cosine: a glossy one's is near it.
    double sender = 1.0;
    if (d > 0.0 && in.senderNormal != glm::vec3(0.0f)) {
      const double fromLeaf = -glm::dot(Vec3(in.senderNormal), in.toSender), fromX = -glm::dot(Vec3(in.senderNormal), wi);
      if (fromLeaf > 0.0 && !(fromX > 0.0)) continue;  // x is behind the sender's plane
      if (fromLeaf > 0.0) sender = std::min(fromX / fromLeaf, 4.0);
    }
    const Rgb e = in.irradiance * (std::clamp(scale, 0.25, 4.0) * sender);
    const double seen = d > 0.0 && in.radius > 0.0 ? in.radius / d : 0.0;
    if (!(seen > 0.25 * width)) {
      sum += f * e * lobeOverDisk(glm::dot(mirror(wi, n), toEye), power, seen * seen);
      continue;
    }
    if (d > 0.0 && in.senderNormal != glm::vec3(0.0f) && in.senderShape.axis != glm::vec3(0.0f)) {
      const Vec3 sn(in.senderNormal);
      sum += f * e * lobeOverRectangle(to, d, wi, in.senderShape, sn, n, toEye, power, reach);
      continue;
    }
    // The sender's disk, evenly bright: directions on a sunflower over it, each carrying irradiance
    // in proportion to its cosine at x (equal solid angles); those below x's horizon send nothing.
    // Its directions lie within `spread` of wi, so their mirrors within it of wi's: none reaches
    // toEye's lobe when the nearest of them, spread nearer than wi's mirror, is beyond the reach.
    const double spread = std::min(seen, 1.2);
    if (beyondLobe(wi, n, toEye, spread, reach)) continue;
    const double r = std::tan(spread);
    Vec3 u, v;
    orthonormalBasis(wi, u, v);
    double weights = 0.0, lit = 0.0;
    for (int j = 0; j < kDiskPoints; ++j) {
      const Vec3 dj = glm::normalize(wi + sunflowerPoint(u, v, r, diskPoints()[std::size_t(j)]));
      const double c = glm::dot(n, dj);
      if (!(c > 0.0)) continue;
      weights += c;
      const double a = glm::dot(mirror(dj, n), toEye);
      lit += c * power(a);
    }
    if (weights > 0.0) sum += f * e * (lit / weights);
  }
  return sum;
}

}  // namespace glossy
