// `glossyhr reference` (the path-traced reference of a scene) and `glossyhr compare` (metrics and a
// false-colour difference between two EXR images).
#pragma once
#include <string>

struct ReferenceArgs {
  std::string scene, out = "out/reference";
  int spp = -1, maxDepth = 64, threads = 0;
  double timeS = -1.0;
  long long seed = 1;
  bool quiet = false;
};
int runReference(const ReferenceArgs& a);

struct CompareArgs {
  std::string a, b, out;
  long mask = -1;
  bool json = false;
};
int runCompare(const CompareArgs& a);
