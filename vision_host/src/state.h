// The VISION-like solver's shared state, internal to vision_host: the hierarchy, the visibility, the
// options and the per-shot scratch every phase reads (cluster samples, intensity tables, counters),
// and the sender and receiver handles of one interaction. Each phase lives in its own file:
// bounds.cpp (bounded radiosity), contour.cpp and transfer.cpp (estimates), shoot.cpp (link-less
// shooting), push_pull.cpp, intensity.cpp (unshot intensity), audit.cpp (energy).
#pragma once
#include <hr/extension.h>
#include <hr/audit_estimators.h>
#include <hr/octamap.h>
#include <hr/phase_clock.h>
#include <hr/solve.h>
#include <vision/curved_visibility.h>
#include <vision/hierarchy.h>

#include <atomic>
#include <vector>

#include "node_view.h"

namespace vision::detail {

/// A node that shoots: a cluster, an element, or a part of a leaf (a rectangle the leaf would split
/// into; its unshot radiosity is the leaf's, uniform). Parts let a sender be refined without
/// creating nodes, so senders never touch the tree that receivers are splitting.
struct Sender {
  std::uint32_t cluster = hr::kNone;  // cluster index, or kNone for an element or part
  const Element* e = nullptr;         // the element, or the leaf a part belongs to
  bool part = false;
  Rect rect;
  std::uint16_t level = 0;
  Geometry g;
  Rgb U{0.0};  // unshot radiosity, W/m^2 (elements and parts)
  Rgb P{0.0};  // unshot power, W
  // The extension's share (hr/extension.h), when it simulates part of the sender: the node it asks
  // (a part asks its leaf, scaled by the part's share of the leaf's area) and its unshot power, W.
  hr::NodeId node;
  double share = 1.0;
  bool owned = false;
  Rgb X{0.0};
  // The visible fraction, when an accepted interaction was handed down to the receiver's children
  // only to place its light (shoot.cpp, settle); negative: trace it.
  double V = -1.0;
  bool dark() const { return P == Rgb(0.0) && X == Rgb(0.0); }
};

/// A node that receives: a cluster or an element (owned by the task that visits it).
struct Receiver {
  std::uint32_t cluster = hr::kNone;
  Element* e = nullptr;
  const Geometry& g(const Hierarchy& h) const { return e ? e->g : h.clusters()[cluster].g; }
};

/// Bounds of the point kernel cos_s cos_r / r^2 (1/m^2) between two nodes, from their boxes and
/// cones of normals; overlap: the boxes meet, so nothing bounds it.
struct KernelBounds {
  double kmin = 0.0, kmax = 0.0;
  bool overlap = false;
  // The parts an extension's bound needs: the cone (axis, half-angle beta; pi: unbounded) of
  // directions from sender to receiver, the receiver's cosine bounds and the squared distance bounds.
  Vec3 axis{0.0, 0.0, 1.0};
  double beta = hr::kPi, rLo = 0.0, rHi = 1.0, rmin2 = 0.0, rmax2 = 0.0;
};

struct State {
  State(const hr::Scene& sc, Hierarchy& hi, const CurvedVisibility& v, const hr::SolverOptions& o)
      : scene(sc), h(hi), vis(v), opt(o) {}
  const hr::Scene& scene;
  Hierarchy& h;
  const CurvedVisibility& vis;
  hr::SolverOptions opt;
  hr::Extension* ext = nullptr;               // additive: it owns only the part it simulates
  const NodeView* view = nullptr;             // what the extension reads of the nodes
  std::vector<std::uint8_t> ownedSurface, ownedCluster;  // the extension simulates a surface inside
  // How sharply each surface reflects through the extension, and each cluster's sharpest (largest
  // albedo, narrowest lobe): empty when no material has a reflector, so the term costs nothing then.
  std::vector<hr::Reflector> surfaceReflector, clusterReflector;

  double emitted = 0.0;     // luminance, W
  double threshold = 0.0;   // eps * emitted: the largest gap a kept interaction may have, W
  double visTolerance = 0.0;
  double minArea = 0.0;
  std::vector<std::vector<ClusterSample>> samples;  // per cluster, this shot
  std::vector<float> tables;                        // OctaMap tables of unshot intensity, W/sr
  std::vector<std::uint32_t> order;                 // surfaces in cluster order
  std::vector<std::uint32_t> first;                 // per cluster: where its surfaces start in order
  std::vector<double> areaPrefix;                   // cumulative area along order
  mutable std::atomic<std::uint64_t> rays{0}, visibilityNs{0};  // counters the const phases bump
  std::atomic<std::uint64_t> handed{0};  // samples handed to the extension's reflection this shot
  // Threads seen working in each phase (bit per TBB thread index): a phase that should be parallel
  // but ran on one thread shows in stats.json.
  mutable std::atomic<std::uint64_t> shootThreads{0}, pushThreads{0}, auditThreads{0};

  const hr::Material& material(const Element& e) const { return scene.materials[h.surfaces()[e.surface].material]; }
  bool owned(const Element& e) const { return ext && ownedSurface[e.surface]; }
  /// Clusters of more surfaces than this keep a table of their unshot intensity.
  static constexpr std::uint32_t kTabled = 16;
  const float* table(const Cluster& c) const { return &tables[std::size_t(c.table) * hr::OctaMap::kBins * 3]; }
};


// bounds.cpp
KernelBounds kernelBounds(const Geometry& s, const Geometry& r);
/// A point x with unit normal n, as a node of zero size.
Geometry pointGeometry(const Vec3& x, const Vec3& n);

// contour.cpp
/// Form factor from a differential area at x (unit normal n) to the surface bounded by the closed
/// polyline pts, seen from its front (Lambert's contour integral); clipped to x's horizon when clip.
double contourFormFactor(const Vec3& x, const Vec3& n, const std::vector<Vec3>& pts, bool clip);
/// Form factor from a differential area at x (normal n) to a rectangle of a curved surface that x may
/// see only in part: split until each piece faces x wholly (contour) or not at all.
double curvedFormFactor(const Surface& sf, const Rect& r, const Vec3& x, const Vec3& n);
/// Pieces down to 4^-kMaxSplits of the rectangle's parameter area.
constexpr int kMaxSplits = 4;
/// curvedFormFactor for one curved sender seen from many points (the receiver's quadrature points):
/// its probes (points and normals on a lattice of the rectangle) and the outlines of its pieces
/// are made on first use and kept. Surface maps cost sines and cosines, and probing the same
/// pieces again for every point was half of a shot on the Soda Shoppe. One thread, one estimate.
class CurvedPieces {
 public:
  CurvedPieces(const Surface& sf, const Rect& r);
  /// Starts over for another rectangle, keeping the storage: curvedFormFactor makes one per call,
  /// and a concave receiver's point asks for 32 (insideFormFactor); allocating their tables each
  /// time was a quarter of a curved furnace's time under AddressSanitizer (80 -> 41 s without it).
  void reset(const Surface& sf, const Rect& r);
  double formFactor(const Vec3& x, const Vec3& n) { return piece(0, 0, 0, x, n); }
  /// Whether the rectangle's corners, edge midpoints and centre all face x (within tol).
  bool topFaces(const Vec3& x, double tol);

 private:
  static constexpr int kN = 2 << kMaxSplits;  // lattice intervals per side: every probe of every piece
  double piece(int depth, int i, int j, const Vec3& x, const Vec3& n);
  Rect rectOf(int depth, int i, int j) const;
  std::size_t probe(int i, int j);
  const Surface* sf_;
  Rect r_;
  std::vector<std::int32_t> slot_, outlineSlot_;  // lattice point / piece -> its place, -1 not made
  std::vector<Vec3> p_, n_;
  std::vector<std::vector<Vec3>> outlines_;  // the first outlineCount_ are this rectangle's
  std::size_t outlineCount_ = 0;
};
/// The same for x on a concave surface at (u, v) inside the rectangle r of that surface.
double insideFormFactor(const Surface& sf, const Rect& r, double u, double v, const Vec3& x, const Vec3& n);
/// The outline of a rectangle of a surface, counter-clockwise about its front, curved edges as
/// chords turning at most about 3 degrees.
void outline(const Surface& s, const Rect& r, std::vector<Vec3>& out);

// intensity.cpp
/// Unshot radiant intensity of a sender toward unit dir, W/sr.
Rgb unshotIntensity(const State& s, const Sender& snd, const Vec3& dir);
/// Tables of unshot intensity for the large clusters (after the pull). Parallel.
void buildTables(State& s);

// extension_light.cpp: the extension's share of a sender's unshot light (none without one)
/// Sets a sender's node, share, owned flag and unshot power of the extension.
void extensionSender(const State& s, Sender& x);
/// Its unshot intensity toward unit dir, W/sr.
Rgb extensionIntensity(const State& s, const Sender& x, const Vec3& dir);
/// Its unoccluded irradiance on an element receiver whose mean form factor to the sender is F, W/m^2
/// (a flat sender's light as a radiosity that F turns into irradiance, as the host's own).
Rgb extensionIrradiance(const State& s, const Sender& x, const Element& r, double F);
/// How far the power it brings the receiver may be off, W (luminance); `coarse`: from its peak
/// over all directions, without looking at any.
double extensionGap(const State& s, const Sender& x, const Geometry& r, const KernelBounds& kb, bool coarse);
/// Its unshot power left in the whole scene, W (luminance).
double extensionUnshot(const State& s);

// transfer.cpp
struct Estimate {
  Rgb E{0.0};             // element receiver: mean irradiance; cluster receiver: E_perp; W/m^2
  Vec3 toSender{0.0};     // receiver -> sender, unit
  double distance = 0.0;  // between the two centres, m
  double radius = 0.0;    // the sender's, as hr::IncidentSample::radius
  glm::vec3 senderNormal{0.0f};  // a flat element sender's, as hr::IncidentSample::senderNormal
  hr::SenderRectangle senderShape;  // and its shape, as hr::IncidentSample::senderShape
  double unoccluded = 0.0;  // power it would bring without occlusion (luminance), W
  double V = 1.0;           // visible fraction
  double sigma = 0.0;       // standard error of V
  bool mixed = false;       // some rays visible, some blocked
  // Element receivers from an element sender: the mean form factor over each quarter of the
  // receiver's parameter rectangle (u low/high + 2 * v low/high), how the light falls across it.
  bool quarters = false;
  double quarterF[4] = {0.0, 0.0, 0.0, 0.0};
};
/// An element receiver's quadrature points for estimate(): position, normal and Jacobian weight at
/// Gauss-Legendre nodes (3 x 3 for far senders, 5 x 5 for near ones), made on first use and kept for
/// the receiver's other senders (surface maps cost sines and cosines: most of a shot's time).
struct ReceiverPoints {
  struct Grid {
    bool made = false;
    std::vector<Vec3> p, n;
    std::vector<double> w;  // Gauss weight times Jacobian
  };
  Grid grid[2];  // 3 x 3, 5 x 5
};
Estimate estimate(const State& s, const Sender& snd, const Receiver& r, ReceiverPoints* points = nullptr);

// shoot.cpp
/// One shot: every node's unshot light to every receiver, interactions derived top-down and not
/// kept. Returns the interactions used.
std::uint64_t shoot(State& s);

// push_pull.cpp
/// Pushes this shot's light down to the leaves (new unshot = rho E, replacing the light just shot),
/// pulls power and radiosity up; returns the unshot power left (luminance, W). push = false only
/// pulls: before the first shot, when the leaves' unshot light is their emission.
double pushPull(State& s, bool push = true);
/// Surfaces in cluster order with their area prefix (once, after the hierarchy is built).
void indexClusters(State& s);

// audit.cpp
hr::audit::Totals auditEnergy(const State& s);

}  // namespace vision::detail
