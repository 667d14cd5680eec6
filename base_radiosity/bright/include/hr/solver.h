// The diffuse hierarchical radiosity solver with clustering: link refinement from the root
// cluster's self-link, Embree visibility, Jacobi gathering with re-refinement, push/pull. An optional
// Extension receives the four hooks (gather, push/pull, reflect, display); without one this is the
// plain diffuse core. See docs/solver.md for the refinement oracle and the transfer kernels.
#pragma once
#include <hr/extension.h>
#include <hr/hierarchy.h>
#include <hr/progress.h>
#include <hr/solution.h>
#include <hr/solve.h>
#include <hr/visibility.h>

#include <memory>

namespace hr {

class Solver {
 public:
  Solver(const Scene& scene, Hierarchy& hierarchy, const Visibility& vis, const SolverOptions& opt,
         Extension* extension = nullptr, Progress* progress = nullptr);
  ~Solver();
  SolveStats solve();

  /// Radiosity per element (W/m^2), valid for leaves and, area-averaged, for inner elements; over
  /// the element's open part (openFraction) where a coplanar patch covers some of it.
  const std::vector<Rgb>& radiosity() const;
  /// Per element, the fraction of its area no coplanar patch covers (1 almost always; 0 under a
  /// box's foot): what radiosity() and irradiance() apply to, and the weight of an area mean.
  const std::vector<float>& openFraction() const;
  /// Irradiance per element (W/m^2) from the last push.
  const std::vector<Rgb>& irradiance() const;
  const HostView& view() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The solved quadtree as a host-independent hr::Solution (every output reads that), with the
/// radiosity per element (W/m^2) that Solver::radiosity() returns. host = "bright".
Solution makeSolution(const Scene& scene, const Hierarchy& h, const std::vector<Rgb>& radiosity);

}  // namespace hr
