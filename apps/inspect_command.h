// `glossyhr inspect`: one element of a saved solution, found by id or by a point on it: what it
// holds (material, radiosity, the extension's coefficients and power) and, with -o, its exitant
// radiant intensity as a VTK lobe surface that ParaView opens.
#pragma once
#include <string>
#include <vector>

struct InspectArgs {
  std::string solution, out;
  long long element = -1;
  std::vector<double> point;
  bool json = false;
};

int runInspect(const InspectArgs& a);
