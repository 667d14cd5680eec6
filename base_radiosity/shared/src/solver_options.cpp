// Solver options from a scene's settings, the same for every host (the command line overrides
// them afterwards, in apps/).
#include <hr/solve.h>

#include <cstdlib>
#include <string>

namespace hr {

SolverOptions SolverOptions::from(const Settings& s) {
  SolverOptions o;
  o.eps = s.eps;
  o.maxLevel = s.maxLevel;
  o.minArea = s.minArea;
  o.raysPerLink = s.raysPerLink;
  o.maxIterations = s.maxIterations;
  o.tolerance = s.tolerance;
  o.seed = s.seed;
  const char* testOnly = std::getenv("GLOSSYHR_TEST_ONLY_UNBLOCKED_SHADOW_RAYS");
  o.testOnlyUnblockedShadowRays = testOnly && std::string(testOnly) == "1";
  return o;
}

}  // namespace hr
