// The VISION-like host (paper §6): whole primitives as initial patches, elements in parameter space,
// bounded radiosity refinement and link-less shooting. It reads the same scenes and options as the
// tessellating host and reports the same statistics; makeSolution() turns its result into the
// host-independent hr::Solution that every output (images, .vtp, .ghrs, `render`) reads. An
// extension (hr/extension.h) joins through the same hooks as on the other host; it must shoot.
// docs/hosts.md explains the design and the figures.
#pragma once
#include <hr/progress.h>
#include <hr/solution.h>
#include <hr/solve.h>
#include <vision/curved_visibility.h>
#include <vision/hierarchy.h>

#include <memory>

namespace vision {

class Solver {
 public:
  /// Throws hr::InputError when ext cannot shoot (this host shoots only).
  Solver(const hr::Scene& scene, Hierarchy& h, const CurvedVisibility& vis, const hr::SolverOptions& opt,
         hr::Extension* ext = nullptr, hr::Progress* progress = nullptr);
  ~Solver();
  /// Shoots until the unshot power is below tolerance * emitted (or maxIterations), then audits.
  /// counts.links is 0 (nothing is stored); linksComputed counts every interaction estimated.
  hr::SolveStats solve();
  /// Unshot power left when the run ended, W (luminance): light the solution has not yet moved.
  double unshotW() const;
  /// Share of the shooting threads' time spent tracing shadow rays.
  double visibilityShare() const;
  /// The nodes as an extension sees them; valid as long as the solver.
  const hr::HostView& view() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// How a solution is shown: one value per element (as VISION), or smoothed per vertex where
/// elements meet (hr::reconstruct).
enum class Display { Flat, Smooth };

/// The solved hierarchy as an hr::Solution: every leaf becomes small flat polygons (curved ones
/// turning at most 7.5 degrees each) carrying the leaf's radiosity, so `render` and the .vtp need
/// nothing of this host. host = "vision".
/// cellLeaf, if given, receives per solution element the element id (NodeId) of the leaf it shows.
hr::Solution makeSolution(const hr::Scene& scene, const Hierarchy& h, Display display,
                          std::vector<std::uint32_t>* cellLeaf = nullptr);

/// Elements and leaves of the element trees.
struct TreeCounts {
  std::size_t elements = 0, leaves = 0;
};
TreeCounts countElements(const Hierarchy& h);

}  // namespace vision
