// `glossyhr reference` (the path-traced reference of a scene) and `glossyhr compare` (metrics and a
// false-colour difference between two EXR images).
#pragma once
#include <optional>
#include <string>
#include <vector>

struct ReferenceArgs {
  std::string scene, out = "out/reference";
  std::optional<int> spp, threads;
  int maxDepth = 64;
  std::optional<double> timeS;
  long long seed = 1;
  bool quiet = false;
};
int runReference(const ReferenceArgs& a);

struct CompareArgs {
  std::string a, b, out;
  std::string variance;  // B's variance image (.var.exr): the reference's own noise taken out
  std::optional<long long> mask;
  std::vector<long long> exclude;  // objects left out (the light sources, say)
  std::string lightsOf;            // a scene whose emitting objects are left out as well
  bool json = false;
};
int runCompare(const CompareArgs& a);
