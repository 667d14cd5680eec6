// Grid specs to configurations. Every configuration carries its algorithm (diffuse when the grid does
// not say), then the keys in the grid's order; duplicates that appear once keys are dropped are
// removed keeping the first, so the sweep's order is the spec's.
#include "grid.h"

#include <hr/echo.h>
#include <hr/scene.h>

#include <algorithm>
#include <set>
#include <sstream>

namespace study {
namespace {

std::string trim(const std::string& s) {
  auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, sep)) out.push_back(trim(item));
  if (!s.empty() && s.back() == sep) out.push_back("");
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

/// One cartesian product ("KEY=V,V;KEY=V"), its configurations appended to `out` unless already there.
void parseProduct(const std::string& spec, const GridKeys& keys, std::vector<Config>& out, std::set<Config>& known) {
  std::vector<std::string> valid = {"algorithm"};
  valid.insert(valid.end(), keys.core.begin(), keys.core.end());
  std::vector<std::string> algorithms;
  for (const auto& [name, opts] : keys.byAlgorithm) {
    algorithms.push_back(name);
    for (const auto& o : opts)
      if (std::find(valid.begin(), valid.end(), o) == valid.end()) valid.push_back(o);
  }
  std::vector<std::pair<std::string, std::vector<std::string>>> axes;
  for (const std::string& part : split(spec, ';')) {
    if (part.empty()) continue;
    auto eq = part.find('=');
    if (eq == std::string::npos)
      throw hr::InputError("--grid: " + hr::echo(part) + " is not KEY=VALUE,VALUE,...");
    std::string key = trim(part.substr(0, eq));
    if (std::find(valid.begin(), valid.end(), key) == valid.end())
      throw hr::InputError("--grid: unknown key " + hr::echo(key) + " (keys: " + join(valid) + ")");
    for (const auto& a : axes)
      if (a.first == key) throw hr::InputError("--grid: key " + hr::echo(key) + " given twice");
    std::vector<std::string> values = split(part.substr(eq + 1), ',');
    std::set<std::string> seen;
    for (const auto& v : values) {
      if (v.empty()) throw hr::InputError("--grid: " + key + ": an empty value");
      if (!seen.insert(v).second) throw hr::InputError("--grid: " + key + ": value " + hr::echo(v) + " repeated");
      if (key == "algorithm" && std::find(algorithms.begin(), algorithms.end(), v) == algorithms.end())
        throw hr::InputError("--grid: algorithm " + hr::echo(v) + " is not in the table (" + join(algorithms) + ")");
    }
    axes.emplace_back(key, values);
  }
  auto alg = std::find_if(axes.begin(), axes.end(), [](const auto& a) { return a.first == "algorithm"; });
  if (alg == axes.end()) axes.insert(axes.begin(), {"algorithm", {"diffuse"}});
  else std::rotate(axes.begin(), alg, alg + 1);

  std::vector<std::size_t> idx(axes.size(), 0);
  while (true) {
    Config c;
    const std::string& algorithm = axes[0].second[idx[0]];
    const std::vector<std::string>* own = nullptr;
    for (const auto& [name, opts] : keys.byAlgorithm)
      if (name == algorithm) own = &opts;
    for (std::size_t k = 0; k < axes.size(); ++k) {
      const std::string& key = axes[k].first;
      bool applies = k == 0 || std::find(keys.core.begin(), keys.core.end(), key) != keys.core.end() ||
                     (own && std::find(own->begin(), own->end(), key) != own->end());
      if (applies) c.emplace_back(key, axes[k].second[idx[k]]);
    }
    if (known.insert(c).second) out.push_back(c);
    std::size_t k = axes.size();
    while (k > 0) {
      --k;
      if (++idx[k] < axes[k].second.size()) break;
      idx[k] = 0;
      if (k == 0) return;
    }
  }
}

}  // namespace

std::vector<Config> parseGrid(const std::string& spec, const GridKeys& keys) {
  std::vector<Config> out;
  std::set<Config> seen;
  std::vector<std::string> products = split(spec, '|');
  for (const std::string& p : products) {
    if (products.size() > 1 && trim(p).empty()) throw hr::InputError("--grid: an empty product between '|'");
    parseProduct(p, keys, out, seen);
  }
  return out;
}

std::string label(const Config& c) {
  std::string s;
  for (const auto& [k, v] : c) s += (s.empty() ? "" : " ") + k + "=" + v;
  return s;
}

std::string value(const Config& c, const std::string& key) {
  for (const auto& [k, v] : c)
    if (k == key) return v;
  return "";
}

}  // namespace study
