// A study's grid: the configurations `glossyhr study` sweeps, each a list of `solve` flags. The grid
// is a cartesian product of keys and values ("algorithm=diffuse,is;eps=1e-3,1e-4;basis=haar,sh");
// keys an algorithm does not take (a directional basis for the diffuse core) are dropped for it, so
// a configuration is never solved twice under two names. Products joined by '|' are swept one after
// the other ("basis=haar;dir-max-level=3,4 | basis=tetra;tetra-level=3,4"): each basis's own curve in
// one study, without the products of options that only another basis reads.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace study {

using Flag = std::pair<std::string, std::string>;  // solve's option without "--", its value
using Config = std::vector<Flag>;

struct GridKeys {
  std::vector<std::string> core;  // options every algorithm takes (eps, max-level, ...)
  // options each algorithm takes besides: algorithm name, its option names
  std::vector<std::pair<std::string, std::vector<std::string>>> byAlgorithm;
};

/// Throws hr::InputError naming the key or value (and listing the valid keys) on a malformed spec, an
/// unknown key, an algorithm not in the table, an empty value list, or a value repeated under a key.
std::vector<Config> parseGrid(const std::string& spec, const GridKeys& keys);

/// "algorithm=is eps=1e-4 basis=haar": a configuration's label in the CSV, plots and progress.
std::string label(const Config& c);

/// The value of one key in a configuration, or "" when the configuration does not set it.
std::string value(const Config& c, const std::string& key);

}  // namespace study
