// A leaf's brightest incident light, kept for the display. A leaf's distribution holds what it
// reflects only as means over its stored cells, reflected about the leaf's centre: a small bright
// source's highlight is then as wide as a cell, and on a curved surface it sits where the leaf's
// centre puts it. So a leaf also keeps its brightest samples (each at least kShownShare of the
// irradiance its samples bring, from a sender seen no wider than kShownWidth lobe widths, at most
// kShownSamples of them; a flat sender's pieces joined into one where they would fall under the
// share or beyond the count, as a fine solution's lamp does), and a display view that names its
// point (still images' curved leaves, per pixel; not display vertices, where it would cost a cell
// integral each and alias) adds, inside the one cell it reads, their reflection at the point and
// normal it shows, the source integrated over its rectangle (a flat sender's shape, hr/sender_shape.h)
// or its disk and re-aimed from that point, minus that
// cell's mean of the same samples' lobes as the solve deposited them. Over every cell the addition
// averages to the sources' exact reflection instead of their deposited lobes, so the display's light
// per cell stays the solution's and a highlight takes the source's shape (floor_gloss's shiny sphere:
// docs/glossy.md, "Highlights at display"). The solve itself never reads these samples.
#pragma once
#include <glossy/frame.h>
#include <glossy/spherical_geometry.h>
#include <hr/extension.h>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace glossy {

inline constexpr int kShownSamples = 16;
inline constexpr double kShownShare = 1.0 / 64.0;
inline constexpr double kShownWidth = 2.0;  // the widest source kept, in lobe widths: a highlight's, not a scene's
// How near (lobe widths) to a group's centre pieces of one flat sender may be to be shown as one,
// narrowest first.
inline constexpr double kMergeWidths[] = {0.125, 0.25, 0.5};
inline constexpr int kMaxPieces = 256;  // the brightest samples looked at for joining
inline constexpr double kPieceShare = kShownShare / 16.0;  // the least share a piece to be joined brings

/// A number no other object of its kind had in this process, drawn anew by every copy: a memo keyed
/// by it (shownCellMean's) can never read a freed object's entry through a reused address.
class Identity {
 public:
  Identity() : value_(next()) {}
  Identity(const Identity&) : value_(next()) {}
  Identity& operator=(const Identity&) {
    value_ = next();
    return *this;
  }
  std::uint64_t value() const { return value_; }

 private:
  static std::uint64_t next();
  std::uint64_t value_;
};

struct ShownLight {
  /// A sample as a leaf received it: aimed from `from` (m, that leaf's centre), its irradiance on the
  /// plane of `normal` (that leaf's: a leaf split later hands its samples to its children). Floats:
  /// the display needs no more, and a leaf may keep kShownSamples of them.
  struct Sample {
    glm::vec3 toSender{0, 0, 1}, irradiance{0.0f}, from{0.0f}, normal{0, 0, 1};
    glm::vec3 senderNormal{0.0f};          // a flat sender's (hr::IncidentSample::senderNormal); 0: none
    float distance = 0.0f, radius = 0.0f;  // m; distance 0: unknown
    hr::SenderRectangle senderShape;       // a flat sender's shape (hr::IncidentSample::senderShape)
    // A joined sample's pieces as the solve reflected them: deposited[firstPiece, + pieces); 0: itself.
    std::uint32_t firstPiece = 0, pieces = 0;
    hr::IncidentSample in() const {
      return {Vec3(toSender), Rgb(irradiance), double(distance), double(radius), senderNormal, senderShape};
    }
  };
  std::vector<Sample> samples;  // the brightest first
  // The joined samples' pieces, each as the solve deposited it (none joined itself): the cell mean
  // the display takes out is of these, the lobes the stored distribution holds, not of the joined
  // source, which the solve never reflected (docs/glossy.md, "Pieces taken out as deposited").
  std::vector<Sample> deposited;
  /// A joined sample's pieces (none for a sample that is itself).
  std::span<const Sample> piecesOf(const Sample& x) const {
    return {deposited.data() + x.firstPiece, x.pieces};
  }
  double total = 0.0;           // luminance of all the irradiance the leaf received, W/m^2
  Rgb specular{0.0};            // the material's rho_s
  double exponent = 1.0;        // the Phong exponent the leaf reflected with
  int level = 0;               // the Haar level the leaf's lobes were integrated at (its finest)
  int senderPoints = 0;         // makeLobes' senderPoints
  Identity identity;            // filled once, then read only (shared as const)
};

/// The brightest of a leaf's samples as its ShownLight, or null when none qualifies (no light, or a
/// leaf lit evenly by many senders, whose cells already show it).
std::shared_ptr<const ShownLight> keepShown(std::span<const hr::IncidentSample> samples, const Vec3& from,
                                            const Vec3& normal, const Rgb& specular, double exponent,
                                            int level, int senderPoints);

/// One leaf's shown light of two parts together (a shooting leaf's passes, Radiance Clustering's
/// samples one by one): the samples of both that keep their share of the joint total, the brightest
/// first, a flat sender's pieces from either joined as keepShown joins them. Hosts join in a fixed
/// order; another order may group the pieces otherwise.
std::shared_ptr<const ShownLight> joinShown(const std::shared_ptr<const ShownLight>& a,
                                            const std::shared_ptr<const ShownLight>& b);

/// Mean intensity (W/sr) over the upper Haar cell (level, index) of a leaf's frame of the shown
/// samples' lobes as the solve deposited them (each about its receiving leaf's normal), for a leaf of
/// this frame and area (m^2). Remembered per thread for the display's next pixel in that cell.
Rgb shownCellMean(const ShownLight& s, const Frame& frame, double area, int level, std::uint64_t index, double omega);

/// Radiance (W/(m^2 sr)) toward unit toEye of the shown samples reflected at point x (m) of a
/// surface of unit normal n: each source re-aimed from x, its irradiance carried from its leaf's plane,
/// distance and (a flat sender's) foreshortening to x's, and integrated over its rectangle (a flat
/// sender of known shape) or its disk.
Rgb shownRadiance(const ShownLight& s, const Vec3& x, const Vec3& n, const Vec3& toEye);

}  // namespace glossy
