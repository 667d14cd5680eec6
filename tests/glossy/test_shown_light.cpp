// The display's shown light (glossy/shown_light.h) against closed forms and a conservation law: a
// point source's highlight is the modified Phong lobe f_s E at every view, not its mean over a stored
// cell; seen from another point of the leaf the source is re-aimed from there; over the hemisphere the
// display sends the leaf's reflected power (the correction is zero-mean over every cell); a leaf lit
// evenly by many senders, or by a sender much wider than its lobe, keeps none; and off
// (--exact-highlights off) is the stored distribution alone, as is a view without a point (display
// vertices, the viewer); the cell means the display remembers are its own leaf's and shown light's.
#include <glossy/brdf.h>
#include <glossy/cell_rules.h>
#include <glossy/frame.h>
#include <glossy/illumination_samples.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "fake_host.h"

namespace {

using glossy::Rgb;
using glossy::Vec3;
using glossy::kPi;
using testhost::NodeId;

const Rgb kE(2.0, 1.0, 0.5);  // W/m^2, planar irradiance
constexpr double kN = 200.0;  // the lobe: 0.1 rad wide, narrower than the default cells (level 4: 0.1 rad)

/// A floor leaf (normal +z) of the standard scene reflecting the given samples, with the options.
struct Lit {
  testhost::Scene scene{kN};
  std::unique_ptr<glossy::IlluminationSamples> ext;
  NodeId leaf;
  Lit(const std::vector<hr::IncidentSample>& s, const std::vector<hr::OptionValue>& o = {})
      : ext(testhost::configured(o)), leaf(scene.floorLeaves[0]) {
    ext->attach(scene.host);
    ext->reflect(leaf, s);
  }
  Vec3 centre() const { return scene.host.info(leaf).center; }
  /// What a still image shows at the leaf's centre (the shown light needs the point shown).
  Rgb shown(const Vec3& toEye) const { return ext->radiance(leaf, toEye, Vec3(0.0), centre()); }
  /// The modified Phong lobe's radiance, rho_s (n + 2) / (2 pi) cos^n(alpha) E, W/(m^2 sr).
  Rgb phong(const Vec3& wi, const Vec3& toEye, const Rgb& e) const {
    const double a = glm::dot(glossy::mirror(wi, Vec3(0, 0, 1)), toEye);
    return scene.host.materials[0].specular * ((kN + 2.0) / (2.0 * kPi)) * std::pow(std::max(a, 0.0), kN) * e;
  }
};

hr::IncidentSample pointSource(const Vec3& wi, const Rgb& e, double distance) {
  hr::IncidentSample s = testhost::sample(wi, e);
  s.distance = distance;
  return s;
}

/// Views in a fan about direction m, in the plane of m and the normal and across it.
std::vector<Vec3> fan(const Vec3& m) {
  std::vector<Vec3> out;
  const Vec3 side = glm::normalize(glm::cross(Vec3(0, 0, 1), m)), up = glm::normalize(glm::cross(m, side));
  for (int i = -40; i <= 40; ++i)
    for (const Vec3& axis : {side, up}) out.push_back(glm::normalize(m + std::tan(i * 0.005) * axis));
  return out;
}

TEST(ShownLight, APointSourcesHighlightIsTheLobeAtEveryView) {
  // The source 3 m away, 35 degrees from the normal. Over views within 0.2 rad of the mirror
  // direction the display gives the lobe itself: within 1e-3 of its peak (the cell mean of the
  // stored floats less the same cell's mean of the lobe, computed again: their difference rounds).
  // The stored distribution alone (off) gives the cell means: off by more than 10 % of the peak.
  const Vec3 wi = testhost::around(Vec3(0, 0, 1), 35.0 * kPi / 180.0, 0.4);
  const std::vector<hr::IncidentSample> s = {pointSource(wi, kE, 3.0)};
  Lit on(s), off(s, {{"exact-highlights", "off"}});
  const Vec3 m = glossy::mirror(wi, Vec3(0, 0, 1));
  const double peak = on.phong(wi, m, kE).x;
  double worstOn = 0.0, worstOff = 0.0;
  for (const Vec3& e : fan(m)) {
    const Rgb want = on.phong(wi, e, kE);
    worstOn = std::max(worstOn, glm::length(on.shown(e) - want) / peak);
    worstOff = std::max(worstOff, glm::length(off.shown(e) - want) / peak);
  }
  std::printf("worst error over the fan, relative to the peak %.4g W/(m^2 sr): %.2e shown, %.3f stored cells alone\n", peak,
              worstOn, worstOff);
  EXPECT_LT(worstOn, 1e-3);
  EXPECT_GT(worstOff, 0.1);
  // Without a point (a display vertex) the stored distribution, bit for bit.
  for (const Vec3& e : fan(m)) EXPECT_EQ(on.ext->radiance(on.leaf, e), off.ext->radiance(off.leaf, e));
}

TEST(ShownLight, ASourceIsReAimedFromThePointShown) {
  // Seen at a point 0.3 m from the leaf's centre, the source (1 m away) lies in another direction:
  // the highlight is the lobe about the mirror of that direction, its irradiance carried to the
  // point (cosine to the normal and inverse square of the distance), exactly.
  const Vec3 wi = testhost::around(Vec3(0, 0, 1), 30.0 * kPi / 180.0, 1.0);
  Lit lit({pointSource(wi, kE, 1.0)});
  const Vec3 at = lit.centre() + Vec3(0.3, -0.1, 0.0), sender = lit.centre() + 1.0 * wi;
  const double d = glm::length(sender - at);
  const Vec3 wx = (sender - at) / d;
  const Rgb e = kE * (wx.z / wi.z) / (d * d);
  const Vec3 m = glossy::mirror(wx, Vec3(0, 0, 1));
  const double peak = lit.phong(wx, m, e).x;
  double worst = 0.0;
  for (const Vec3& v : fan(m)) worst = std::max(worst, glm::length(lit.ext->radiance(lit.leaf, v, Vec3(0.0), at) - lit.phong(wx, v, e)) / peak);
  EXPECT_LT(worst, 1e-3);
  // At the leaf's centre the lobe about the unmoved mirror: the two peaks lie 0.1 rad apart.
  EXPECT_GT(glm::length(m - glossy::mirror(wi, Vec3(0, 0, 1))), 0.1);
}

TEST(ShownLight, AFlatSendersForeshorteningIsCarriedToThePointShown) {
  // A small flat lamp 1 m off whose normal leans 50 degrees from the line to the leaf's centre. Seen
  // from a point 0.3 m away it is foreshortened otherwise: the irradiance there is
  // E (cosR_x / cosR) (cosS_x / cosS) (d / d_x)^2 (Lambert, a point-sized flat source), and the
  // highlight is the lobe of that, within 1e-3 of its peak. Without the sender's normal (a cluster
  // sender) the highlight keeps the leaf's foreshortening: more than 10 % off here. A point behind
  // the lamp's plane gets none of its light.
  const Vec3 wi = testhost::around(Vec3(0, 0, 1), 30.0 * kPi / 180.0, 1.0);
  const Vec3 lampNormal = -testhost::around(wi, 50.0 * kPi / 180.0, 0.3);
  hr::IncidentSample flat = pointSource(wi, kE, 1.0);
  flat.senderNormal = glm::vec3(lampNormal);
  Lit lit({flat}), blind({pointSource(wi, kE, 1.0)});
  const Vec3 at = lit.centre() + Vec3(0.3, -0.1, 0.0), sender = lit.centre() + 1.0 * wi;
  const double d = glm::length(sender - at);
  const Vec3 wx = (sender - at) / d;
  const double cosS = -glm::dot(lampNormal, wi), cosSx = -glm::dot(lampNormal, wx);
  ASSERT_GT(cosSx, 0.0);
  const Rgb e = kE * (wx.z / wi.z) * (cosSx / cosS) / (d * d);
  const Vec3 m = glossy::mirror(wx, Vec3(0, 0, 1));
  const double peak = lit.phong(wx, m, e).x;
  double worst = 0.0, worstBlind = 0.0;
  for (const Vec3& v : fan(m)) {
    worst = std::max(worst, glm::length(lit.ext->radiance(lit.leaf, v, Vec3(0.0), at) - lit.phong(wx, v, e)) / peak);
    worstBlind = std::max(worstBlind, glm::length(blind.ext->radiance(blind.leaf, v, Vec3(0.0), at) - lit.phong(wx, v, e)) / peak);
  }
  std::printf("worst error over the fan, relative to the peak: %.2e with the sender's normal, %.3f without\n", worst, worstBlind);
  EXPECT_LT(worst, 1e-3);
  EXPECT_GT(worstBlind, 0.1);
  // A point beyond the lamp's plane: nothing of the lamp's shown light (the stored cells' remain).
  const Vec3 behind = sender + 0.5 * glm::normalize(glm::cross(lampNormal, Vec3(0, 0, 1))) - 0.3 * lampNormal;
  const Vec3 past(behind.x, behind.y, lit.centre().z);
  ASSERT_LT(-glm::dot(lampNormal, glm::normalize(sender - past)), 0.0);
  Lit off({flat}, {{"exact-highlights", "off"}});
  for (const Vec3& v : fan(glm::normalize(Vec3(0.2, 0.1, 1.0))))
    EXPECT_LE(glm::length(lit.ext->radiance(lit.leaf, v, Vec3(0.0), past)), glm::length(off.ext->radiance(off.leaf, v)) + 1e-9);
}

TEST(ShownLight, ASmallSourcesHighlightIsTheLobesMeanOverItsDisk) {
  // A source seen 0.02 rad wide in radius, a fifth of the lobe's width (under the quarter above which
  // the display integrates its disk point by point). Its highlight is the lobe's mean over the disk,
  // here computed on a polar grid of 200 x 400 directions: within 2e-3 of the peak over the fan. The
  // lobe at the disk's centre alone is 2 % bright at the peak (n rho^2 / 4).
  const Vec3 wi = testhost::around(Vec3(0, 0, 1), 35.0 * kPi / 180.0, 0.4);
  hr::IncidentSample small = pointSource(wi, kE, 2.0);
  small.radius = 0.04;
  Lit lit({small});
  const double rho = small.radius / small.distance;
  Vec3 u, v;
  glossy::orthonormalBasis(wi, u, v);
  auto diskMean = [&](const Vec3& toEye) {  // cosine-weighted, as the irradiance is
    Rgb sum(0.0);
    double w = 0.0;
    for (int i = 0; i < 200; ++i)
      for (int j = 0; j < 400; ++j) {
        const double r = rho * std::sqrt((i + 0.5) / 200.0), p = 2.0 * kPi * (j + 0.5) / 400.0;
        const Vec3 d = glm::normalize(wi + std::tan(r) * (std::cos(p) * u + std::sin(p) * v));
        sum += d.z * lit.phong(d, toEye, kE), w += d.z;
      }
    return sum / w;
  };
  const Vec3 m = glossy::mirror(wi, Vec3(0, 0, 1));
  const double peak = diskMean(m).x;
  double worst = 0.0;
  for (const Vec3& e : fan(m)) worst = std::max(worst, glm::length(lit.shown(e) - diskMean(e)) / peak);
  const double centre = lit.phong(wi, m, kE).x;
  std::printf("disk mean at the peak %.5g, lobe at its centre %.5g (%+.2f %%), worst display error %.2e of the peak\n", peak,
              centre, 100.0 * (centre / peak - 1.0), worst);
  EXPECT_LT(worst, 2e-3);
  EXPECT_GT(centre / peak - 1.0, 0.01);
}

/// A square lamp of this side (m), `distance` m off along wi from the point c and facing it, of
/// radiance L (W/(m^2 sr)), in k x k pieces as a fine solution reaches a leaf at c (normal +z): each
/// a flat sender's sample, or with no sender normal when `flat` is false.
std::vector<hr::IncidentSample> lampPieces(const Vec3& c, const Vec3& wi, double side, double distance, double L, int k,
                                           bool flat) {
  const double h = side / k;
  Vec3 u, v;
  glossy::orthonormalBasis(wi, u, v);
  const Vec3 lamp = c + distance * wi;
  std::vector<hr::IncidentSample> out;
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      const Vec3 p = lamp + ((i + 0.5) * h - 0.5 * side) * u + ((j + 0.5) * h - 0.5 * side) * v, to = p - c;
      const double d = glm::length(to), cosS = glm::dot(wi, to / d);
      hr::IncidentSample s = pointSource(to / d, Rgb(L * h * h * (to.z / d) * cosS / (d * d)), d);
      s.radius = hr::senderDiskRadius(h * h / 6.0, cosS);
      if (flat) s.senderNormal = glm::vec3(-wi);
      out.push_back(s);
    }
  return out;
}

TEST(ShownLight, ALampInManyPiecesShowsOneHighlight) {
  // A square lamp a lobe's width across, 2 m off and facing the leaf, as a fine solution reaches a
  // leaf: in 12 x 12 pieces, each under the 1/64 share and more of them than a leaf keeps. Its
  // highlight is the sum of the pieces' lobes (each a 120th of the lobe's width: a point): the
  // display within 0.6 % of its peak over the fan (1.8 % with the joined sample's own lobe taken out
  // of its cell instead of its pieces'), the pieces of the flat sender joined as far as it
  // takes to keep their light. The same pieces without a sender's normal (not known to be one flat
  // sender) are not joined, fall under the share one by one, and leave the highlight to the stored
  // cells: more than 10 % off.
  const Vec3 wi = testhost::around(Vec3(0, 0, 1), 35.0 * kPi / 180.0, 0.4);
  Lit probe({});
  const std::vector<hr::IncidentSample> pieces = lampPieces(probe.centre(), wi, 0.2, 2.0, 60.0, 12, true);
  Lit lit(pieces), blind(lampPieces(probe.centre(), wi, 0.2, 2.0, 60.0, 12, false));
  auto exact = [&](const Vec3& toEye) {
    Rgb sum(0.0);
    for (const hr::IncidentSample& s : pieces) sum += lit.phong(s.toSender, toEye, s.irradiance);
    return sum;
  };
  const Vec3 m = glossy::mirror(wi, Vec3(0, 0, 1));
  const double peak = exact(m).x;
  double worst = 0.0, worstBlind = 0.0;
  for (const Vec3& e : fan(m)) {
    worst = std::max(worst, glm::length(lit.shown(e) - exact(e)) / peak);
    worstBlind = std::max(worstBlind, glm::length(blind.shown(e) - exact(e)) / peak);
  }
  std::printf("peak %.5g W/(m^2 sr); worst error over the fan %.2e of it, %.3f with the pieces left apart\n", peak, worst,
              worstBlind);
  EXPECT_LT(worst, 0.006);
  EXPECT_GT(worstBlind, 0.1);
}

TEST(ShownLight, AJoinedSourceTakesOutItsPiecesAsDeposited) {
  // The display takes out of a cell the mean of the lobes the solve deposited there: for a joined
  // lamp, its pieces' lobes, not one lobe about the joined source, which nothing deposited. So a
  // joined light's cell means at the leaf's level are those of the same light with every piece a
  // sample of its own, cell by cell within 1e-9 of the brightest (seen failing with the joined
  // sample's own lobe taken out, 1.6e-2 of it). Every joined sample's irradiance is its pieces' sum; a
  // shooting leaf's second pass over the same links, twice as bright (joinShown), adds to the same
  // 144 pieces instead of adding 144 more (seen failing at 288), its samples and cells three times
  // the first pass's (seen failing with the second light's pieces not offset in the join).
  const Vec3 wi = testhost::around(Vec3(0, 0, 1), 35.0 * kPi / 180.0, 0.4);
  const std::vector<hr::IncidentSample> pieces = lampPieces(Vec3(0.0), wi, 0.2, 2.0, 60.0, 12, true);
  auto keep = [&](double scale) {
    std::vector<hr::IncidentSample> s = pieces;
    for (hr::IncidentSample& x : s) x.irradiance *= scale;
    return glossy::keepShown(s, Vec3(0.0), Vec3(0, 0, 1), Rgb(0.5), kN, 4, glossy::kSenderPoints);
  };
  const auto one = keep(1.0);
  ASSERT_NE(one, nullptr);
  auto check = [](const glossy::ShownLight& l) {
    std::size_t joined = 0;
    for (const auto& x : l.samples) {
      if (x.pieces == 0) continue;
      ++joined;
      ASSERT_LE(std::size_t(x.firstPiece) + x.pieces, l.deposited.size());
      glm::dvec3 sum(0.0);
      for (const auto& p : l.piecesOf(x)) sum += glm::dvec3(p.irradiance);
      EXPECT_NEAR(sum.x, double(x.irradiance.x), 1e-5 * sum.x);
    }
    EXPECT_GT(joined, 0u);
  };
  check(*one);
  std::printf("%zu samples, %zu pieces as deposited\n", one->samples.size(), one->deposited.size());
  glossy::ShownLight apart = *one;  // a copy: another identity, so no remembered cell mean is shared
  apart.samples.clear(), apart.deposited.clear();
  for (const auto& x : one->samples)
    if (x.pieces == 0) apart.samples.push_back(x);
    else apart.samples.insert(apart.samples.end(), one->piecesOf(x).begin(), one->piecesOf(x).end());
  const glossy::Frame up = glossy::Frame::around(Vec3(0, 0, 1));
  const std::uint64_t cells = 4u << (2 * 4);  // the leaf's level, 4
  std::vector<double> joinedMeans(cells), apartMeans(cells);
  for (std::uint64_t i = 0; i < cells; ++i) {
    const double omega = glossy::UpperCells::cell(4, i).solidAngle();
    joinedMeans[i] = glossy::shownCellMean(*one, up, 1.0, 4, i, omega).x;
    apartMeans[i] = glossy::shownCellMean(apart, up, 1.0, 4, i, omega).x;
  }
  const double brightest = *std::max_element(apartMeans.begin(), apartMeans.end());
  double worst = 0.0;
  for (std::uint64_t i = 0; i < cells; ++i) worst = std::max(worst, std::abs(joinedMeans[i] - apartMeans[i]));
  std::printf("cell means joined vs apart: worst %.2e of the brightest\n", worst / brightest);
  EXPECT_GT(brightest, 0.0);
  EXPECT_LT(worst, 1e-9 * brightest);
  const auto two = glossy::joinShown(one, keep(2.0));
  ASSERT_NE(two, nullptr);
  check(*two);
  EXPECT_EQ(two->deposited.size(), one->deposited.size()) << "the same links' pieces, added";
  double a = 0.0, b = 0.0;  // the light in every level-2 cell, mean times solid angle
  for (std::uint64_t i = 0; i < 64; ++i) {
    const double omega = glossy::UpperCells::cell(2, i).solidAngle();
    a += glossy::shownCellMean(*one, up, 1.0, 2, i, omega).x * omega;
    b += glossy::shownCellMean(*two, up, 1.0, 2, i, omega).x * omega;
  }
  EXPECT_GT(a, 0.0);
  EXPECT_NEAR(b, 3.0 * a, 1e-5 * a);
}

TEST(ShownLight, JoinedPiecesAreADiskOfTheirSecondMoment) {
  // A lamp 0.02 m square, 2 m off and facing the leaf, in 8 x 8 pieces: joined into one sample whose
  // irradiance is the pieces' sum and whose radius is the whole square's (senderDiskRadius of its
  // second moment side^2 / 6, seen face on), within 1e-3; its direction the square's centre's.
  const Vec3 wi = testhost::around(Vec3(0, 0, 1), 35.0 * kPi / 180.0, 0.4);
  const double side = 0.02;
  const std::vector<hr::IncidentSample> pieces = lampPieces(Vec3(0.0), wi, side, 2.0, 6e4, 8, true);
  Rgb sum(0.0);
  for (const hr::IncidentSample& s : pieces) sum += s.irradiance;
  const auto kept = glossy::keepShown(pieces, Vec3(0.0), Vec3(0, 0, 1), Rgb(0.5), kN, 4, glossy::kSenderPoints);
  ASSERT_NE(kept, nullptr);
  ASSERT_EQ(kept->samples.size(), 1u);
  const glossy::ShownLight::Sample& one = kept->samples[0];
  const double want = hr::senderDiskRadius(side * side / 6.0, 1.0);
  std::printf("radius %.7f m against %.7f m\n", double(one.radius), want);
  EXPECT_NEAR(one.radius, want, 1e-3 * want);
  EXPECT_NEAR(glm::length(Rgb(one.irradiance) - sum), 0.0, 1e-5 * glm::length(sum));
  EXPECT_GT(glm::dot(Vec3(one.toSender), wi), std::cos(1e-5));
}

/// A rectangular lamp (sides along the unit in-plane axes ua and ub, lengths la and lb in m) centred
/// `distance` m off along wi from the point c, with unit normal sn, of radiance L (W/(m^2 sr)), in
/// ka x kb pieces, each a flat sender's sample with its rectangle (or with none when `shaped` is
/// false: a disk of its spread).
std::vector<hr::IncidentSample> rectanglePieces(const Vec3& c, const Vec3& wi, const Vec3& sn,
                                                const Vec3& ua, const Vec3& ub, double la, double lb,
                                                double distance, double L, int ka, int kb, bool shaped) {
  const double ha = la / ka, hb = lb / kb;
  const Vec3 lamp = c + distance * wi;
  std::vector<hr::IncidentSample> out;
  for (int i = 0; i < ka; ++i)
    for (int j = 0; j < kb; ++j) {
      const Vec3 p = lamp + ((i + 0.5) * ha - 0.5 * la) * ua + ((j + 0.5) * hb - 0.5 * lb) * ub, to = p - c;
      const double d = glm::length(to), cosS = -glm::dot(sn, to / d);
      hr::IncidentSample s = pointSource(to / d, Rgb(L * ha * hb * (to.z / d) * cosS / (d * d)), d);
      s.radius = hr::senderDiskRadius((ha * ha + hb * hb) / 12.0, cosS);
      s.senderNormal = glm::vec3(sn);
      if (shaped) {
        const Vec3 longer = 0.5 * std::max(ha, hb) * (ha >= hb ? ua : ub);
        s.senderShape = {glm::vec3(longer), float(0.5 * std::min(ha, hb))};
      }
      out.push_back(s);
    }
  return out;
}

TEST(ShownLight, ARectangularSourcesHighlightIsItsShape) {
  // A lamp of 0.3 x 0.08 m, 2 m off and tilted 40 degrees from facing the leaf, seen 1.4 lobe widths
  // long and a third of one wide, as a coarse solution reaches a leaf: in 2 x 2 pieces, each with its
  // rectangle. The exact highlight, the lamp in 300 x 80 points each reflected by the lobe: the
  // display within 1e-3 of its peak over views up to 0.2 rad from the mirror direction in every
  // direction (a half-width half or 1.5 times the right one reads 3.5e-3 and 5.7e-3). The same pieces
  // as disks of their spread (no shape known): more than 2 % off.
  const Vec3 wi = testhost::around(Vec3(0, 0, 1), 35.0 * kPi / 180.0, 0.4);
  const Vec3 sn = -testhost::around(wi, 40.0 * kPi / 180.0, 1.1);
  const Vec3 ua = glm::normalize(glm::cross(sn, Vec3(0.3, 1.0, 0.2))), ub = glm::cross(sn, ua);
  Lit probe({});
  const Vec3 c = probe.centre();
  const double L = 60.0;
  Lit lit(rectanglePieces(c, wi, sn, ua, ub, 0.3, 0.08, 2.0, L, 2, 2, true)),
      disks(rectanglePieces(c, wi, sn, ua, ub, 0.3, 0.08, 2.0, L, 2, 2, false));
  const std::vector<hr::IncidentSample> fine =
      rectanglePieces(c, wi, sn, ua, ub, 0.3, 0.08, 2.0, L, 300, 80, false);
  auto exact = [&](const Vec3& toEye) {
    Rgb sum(0.0);
    for (const hr::IncidentSample& x : fine) sum += lit.phong(x.toSender, toEye, x.irradiance);
    return sum;
  };
  const Vec3 m = glossy::mirror(wi, Vec3(0, 0, 1));
  const Vec3 side = glm::normalize(glm::cross(Vec3(0, 0, 1), m)), up = glm::normalize(glm::cross(m, side));
  double peak = 0.0, worst = 0.0, worstDisks = 0.0;
  std::vector<std::pair<Vec3, Rgb>> views;
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j) {
      const Vec3 e = glm::normalize(m + std::tan(0.02 * i) * side + std::tan(0.02 * j) * up);
      views.push_back({e, exact(e)});
      peak = std::max(peak, views.back().second.x);
    }
  for (const auto& [e, want] : views) {
    worst = std::max(worst, glm::length(lit.shown(e) - want) / peak);
    worstDisks = std::max(worstDisks, glm::length(disks.shown(e) - want) / peak);
  }
  std::printf("peak %.5g W/(m^2 sr); worst error over 441 views %.2e of it as rectangles, %.3f as disks\n",
              peak, worst, worstDisks);
  EXPECT_LT(worst, 1e-3);
  EXPECT_GT(worstDisks, 0.02);
}

/// The shape of the one sample a leaf at the origin (normal +z) keeps of these pieces; none, and a
/// failure, when it keeps another number of them.
hr::SenderRectangle joinedShape(const std::vector<hr::IncidentSample>& pieces) {
  const auto kept =
      glossy::keepShown(pieces, Vec3(0.0), Vec3(0, 0, 1), Rgb(0.5), kN, 4, glossy::kSenderPoints);
  if (!kept || kept->samples.size() != 1u) {
    ADD_FAILURE() << "kept " << (kept ? kept->samples.size() : 0u) << " samples, not one";
    return {};
  }
  return kept->samples[0].senderShape;
}

TEST(ShownLight, JoinedPiecesAreTheRectangleOfTheirMoments) {
  // The same lamp, 0.02 m long, in 8 x 4 pieces with their rectangles: joined into one sample whose
  // shape is the whole lamp's, a half-axis of 0.01 m along its long side and a half-width of
  // 0.004 m, within 1e-3.
  const Vec3 wi = testhost::around(Vec3(0, 0, 1), 35.0 * kPi / 180.0, 0.4);
  const Vec3 sn = -testhost::around(wi, 40.0 * kPi / 180.0, 1.1);
  const Vec3 ua = glm::normalize(glm::cross(sn, Vec3(0.3, 1.0, 0.2))), ub = glm::cross(sn, ua);
  const hr::SenderRectangle r =
      joinedShape(rectanglePieces(Vec3(0.0), wi, sn, ua, ub, 0.02, 0.008, 2.0, 6e4, 8, 4, true));
  ASSERT_NE(r.axis, glm::vec3(0.0f));
  std::printf("half-axis %.6f m, %.6f of it along the long side; half-width %.6f m\n",
              glm::length(Vec3(r.axis)), std::abs(glm::dot(glm::normalize(Vec3(r.axis)), ua)),
              double(r.halfWidth));
  EXPECT_NEAR(glm::length(Vec3(r.axis)), 0.01, 1e-5);
  EXPECT_GT(std::abs(glm::dot(glm::normalize(Vec3(r.axis)), ua)), 1.0 - 1e-6);
  EXPECT_NEAR(r.halfWidth, 0.004, 4e-6);
  // A square lamp's quarters: their moments are the same along every line in the plane and name no
  // axis; the first piece's does (rounding alone turned squares up to 52 degrees off their sides).
  const hr::SenderRectangle q =
      joinedShape(rectanglePieces(Vec3(0.0), wi, sn, ua, ub, 0.02, 0.02, 2.0, 6e4, 2, 2, true));
  ASSERT_NE(q.axis, glm::vec3(0.0f));
  const Vec3 qa = glm::normalize(Vec3(q.axis));
  EXPECT_GT(std::max(std::abs(glm::dot(qa, ua)), std::abs(glm::dot(qa, ub))), 1.0 - 1e-6);
  EXPECT_NEAR(glm::length(Vec3(q.axis)), 0.01, 1e-5);
  EXPECT_NEAR(q.halfWidth, 0.01, 1e-5);
}

TEST(ShownLight, TheDisplaySendsTheLeafsReflectedPower) {
  // Two small sources and one dim wide one. Per cell the display exchanges the shown samples' mean
  // for their exact lobes, so over the hemisphere A * integral of L cos equals the leaf's reflected
  // power (the stored cells' integral) to the quadrature's accuracy: within 0.5 % (a midpoint rule
  // over 0.25-degree cells). Seen failing without the cell mean taken off: 0.622 W against 0.311 W.
  std::vector<hr::IncidentSample> s = {pointSource(testhost::around(Vec3(0, 0, 1), 0.5, 0.2), kE, 2.0),
                                       pointSource(testhost::around(Vec3(0, 0, 1), 1.0, 2.5), 0.5 * kE, 1.5),
                                       testhost::sample(testhost::around(Vec3(0, 0, 1), 0.3, 4.0), 0.1 * kE)};
  s[1].radius = 0.05;  // seen 0.033 rad wide: integrated over its disk
  Lit lit(s);
  const double area = lit.scene.host.info(lit.leaf).area;
  const int NT = 360, NP = 1440;
  double sum = 0.0;
  for (int i = 0; i < NT; ++i) {
    const double t = (i + 0.5) * 0.5 * kPi / NT;
    for (int j = 0; j < NP; ++j) {
      const double p = (j + 0.5) * 2.0 * kPi / NP;
      const Vec3 e(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
      sum += lit.shown(e).x * std::cos(t) * std::sin(t);
    }
  }
  const double shown = area * sum * (0.5 * kPi / NT) * (2.0 * kPi / NP), stored = lit.ext->reflectedPower(lit.leaf).x;
  std::printf("display power %.6g W, stored %.6g W\n", shown, stored);
  EXPECT_NEAR(shown, stored, 5e-3 * stored);
}

TEST(ShownLight, ALeafLitEvenlyOrByAWideSenderKeepsNone) {
  // 100 equal senders (each 1 % of the light, under the 1/64 share) and a sender 5 lobe widths wide:
  // the display is the stored distribution's, bit for bit.
  auto same = [](const std::vector<hr::IncidentSample>& s) {
    Lit on(s), off(s, {{"exact-highlights", "off"}});
    for (const Vec3& e : fan(glm::normalize(Vec3(0.3, 0.2, 1.0))))
      if (on.shown(e) != off.shown(e)) return false;
    return true;
  };
  std::vector<hr::IncidentSample> even;
  for (int k = 0; k < 100; ++k) even.push_back(pointSource(testhost::around(Vec3(0, 0, 1), 0.2 + 0.01 * k, 0.7 * k), kE, 2.0));
  EXPECT_TRUE(same(even));
  hr::IncidentSample wide = pointSource(testhost::around(Vec3(0, 0, 1), 0.4, 1.0), kE, 1.0);
  wide.radius = 0.5;
  EXPECT_TRUE(same({wide}));
  wide.radius = 0.05;
  EXPECT_FALSE(same({wide}));
}

TEST(ShownLight, ARememberedCellMeanIsTheLeafsOwn) {
  // shownCellMean remembers its answers per thread (a still image asks per pixel). What it returns
  // must be what it would compute: the mean is linear in the leaf's area and in the samples'
  // irradiance, and turns with the leaf's frame. Asked first for one leaf, then for a copy of the
  // shown light three times as bright (a copy is another shown light), a leaf twice as large and a
  // turned one, each answer is the fresh one's. Seen failing with the area left out of the memo's
  // check (1 instead of 2) and with a copy keeping its original's identity (1 instead of 3).
  std::vector<hr::IncidentSample> s = {pointSource(testhost::around(Vec3(0, 0, 1), 0.5, 0.2), kE, 2.0),
                                       pointSource(testhost::around(Vec3(0, 0, 1), 0.7, 2.5), 0.5 * kE, 1.5)};
  const auto shown = glossy::keepShown(s, Vec3(0.0), Vec3(0, 0, 1), Rgb(0.5), kN, 4, glossy::kSenderPoints);
  ASSERT_NE(shown, nullptr);
  // The light in every level-1 cell of a frame, each cell's mean times its solid angle.
  auto total = [](const glossy::ShownLight& l, const glossy::Frame& f, double area) {
    double sum = 0.0;
    for (std::uint64_t i = 0; i < 16; ++i) {
      const double omega = glossy::UpperCells::cell(1, i).solidAngle();
      sum += glossy::shownCellMean(l, f, area, 1, i, omega).x * omega;
    }
    return sum;
  };
  const glossy::Frame up = glossy::Frame::around(Vec3(0, 0, 1)), turned = glossy::Frame::around(glm::normalize(Vec3(0.6, 0, 1)));
  const double first = total(*shown, up, 1.0);
  ASSERT_GT(first, 0.0);
  EXPECT_EQ(total(*shown, up, 1.0), first) << "asked again";
  glossy::ShownLight brighter = *shown;  // asked right after the original, at the same leaf
  for (auto& x : brighter.samples) x.irradiance *= 3.0f;
  EXPECT_NEAR(total(brighter, up, 1.0) / first, 3.0, 1e-6) << "a copy three times as bright";
  EXPECT_NEAR(total(*shown, up, 2.0) / first, 2.0, 1e-12) << "a leaf twice as large";
  // Turned by 31 degrees the frame's cells take the lobes at other places: another answer, and again
  // the same one once remembered.
  const double other = total(*shown, turned, 1.0);
  EXPECT_GT(std::abs(other - first), 1e-3 * first);
  EXPECT_EQ(total(*shown, turned, 1.0), other);
}

TEST(ShownLight, AJoinThatKeepsNothingIsNoShownLight) {
  // A shooting leaf's passes (or Radiance Clustering's samples) joined: 65 equal senders, each 1/65
  // of the joint light, under the 1/64 share. The join keeps none and is no shown light at all (an
  // empty one was saved, and the solution file then refused its own section: "0 samples").
  auto keep = [](int count, double first) {
    std::vector<hr::IncidentSample> s;
    for (int k = 0; k < count; ++k) s.push_back(pointSource(testhost::around(Vec3(0, 0, 1), first + 0.01 * k, 0.3 * k), kE, 2.0));
    return glossy::keepShown(s, Vec3(0.0), Vec3(0, 0, 1), Rgb(0.5), kN, 4, glossy::kSenderPoints);
  };
  const auto one = keep(1, 0.2), many = keep(64, 0.4);
  ASSERT_NE(one, nullptr);
  ASSERT_NE(many, nullptr);
  EXPECT_EQ(many->samples.size(), std::size_t(glossy::kShownSamples));
  EXPECT_EQ(glossy::joinShown(one, many), nullptr);
  EXPECT_EQ(glossy::joinShown(many, one), nullptr);
  EXPECT_EQ(glossy::joinShown(one, one)->samples.size(), 2u);
}

}  // namespace
