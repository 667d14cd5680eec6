// Reflecting a leaf's Illumination Samples: dropping and merging samples, the lobe sum, and the
// projection into each basis (Haar by cell integrals at the stored levels, haar_lobes.cpp;
// tetrahedron and spherical harmonics on a lobe limited to what they can hold).
#include <glossy/brdf.h>
#include <glossy/haar_lobes.h>
#include <glossy/reflection.h>

#include <algorithm>
#include <numeric>

namespace glossy {

Rgb LobeSet::operator()(const Vec3& w) const {
  double c = glm::dot(normal, w);
  if (c <= 0.0) return Rgb(0.0);
  Rgb sum(0.0);
  for (const LobeSample& s : samples) {
    double a = glm::dot(s.mirror, w);
    if (a > 0.0) sum += s.weight * std::pow(std::min(a, 1.0), exponent);
  }
  evaluations += samples.size();
  return c * sum;
}

double mergeAngle(double exponent) { return phongLobeWidth(exponent) / 16.0; }

double representableExponent(const BasisSpec& b, double exponent) {
  auto widest = [&](double width) {
    // The exponent whose 1 % half-width is `width`: cos(width)^N = 0.01.
    double c = std::cos(std::min(width, 0.5 * kPi - 1e-9));
    return std::log(0.01) / std::log(c);
  };
  switch (b.basis) {
    case Basis::Haar: return exponent;
    case Basis::Tetra: {
      // Root edges of the tetrahedron span acos(-1/3) = 109.47 degrees; each level halves them.
      double spacing = std::acos(-1.0 / 3.0) / double(1 << b.tetraLevel);
      return std::min(exponent, widest(2.0 * spacing));
    }
    default: return std::min(exponent, widest(2.0 * kPi / b.shOrder));
  }
}

LobeSet makeLobes(std::span<const hr::IncidentSample> samples, const Frame& frame, const Vec3& worldNormal, double area,
                  const Rgb& specular, double exponent, double merge, ReflectCounts& counts) {
  LobeSet set;
  set.normal = glm::normalize(frame.toLocal(worldNormal));
  set.exponent = exponent;
  counts.received += samples.size();
  const Rgb scale = area * specular * ((exponent + 2.0) / (2.0 * kPi));
  struct Item {
    Vec3 mirror;
    Rgb e;
    double w;  // channel sum of E: the merge weight and order
    std::size_t index;
  };
  std::vector<Item> items;
  items.reserve(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto& s = samples[i];
    double len = glm::length(s.toSender);
    bool ok = hr::allFinite(s.irradiance) && hr::allFinite(s.toSender) && len > 0.0 &&
              glm::all(glm::greaterThanEqual(s.irradiance, Rgb(0.0))) && hr::maxComponent(s.irradiance) > 0.0;
    Vec3 wi = ok ? frame.toLocal(s.toSender / len) : Vec3(0.0);
    double cosI = glm::dot(set.normal, wi);
    if (!ok || !(cosI > 0.0)) {
      ++counts.dropped;
      continue;
    }
    items.push_back({mirror(wi, set.normal), s.irradiance, s.irradiance.x + s.irradiance.y + s.irradiance.z, i});
  }
  // Brightest first (ties by arrival order): each sample joins the first kept sample within `merge`
  // of it, so every merged direction lies within `merge` of its group's brightest member.
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.w != b.w ? a.w > b.w : a.index < b.index; });
  struct Group {
    Vec3 seed, sum;
    Rgb e;
  };
  std::vector<Group> groups;
  const double cosMerge = merge > 0.0 ? std::cos(merge) : 2.0;
  for (const Item& it : items) {
    Group* g = nullptr;
    for (Group& c : groups)
      if (glm::dot(c.seed, it.mirror) >= cosMerge) {
        g = &c;
        break;
      }
    if (!g) {
      groups.push_back({it.mirror, Vec3(0.0), Rgb(0.0)});
      g = &groups.back();
    }
    g->sum += it.w * it.mirror;
    g->e += it.e;
  }
  set.samples.reserve(groups.size());
  for (const Group& g : groups) {
    double len = glm::length(g.sum);
    set.samples.push_back({len > 0.0 ? g.sum / len : g.seed, scale * g.e});
  }
  counts.kept += set.samples.size();
  return set;
}

AnyDistribution zeroDistribution(const BasisSpec& b) {
  switch (b.basis) {
    case Basis::Haar: return HaarDistribution();
    case Basis::Tetra: return TetraDistribution(b.tetraLevel);
    default: return ShDistribution(b.shOrder);
  }
}

AnyDistribution projectLobes(const LobeSet& lobes, const BasisSpec& b, ReflectCounts& counts) {
  if (lobes.samples.empty()) return zeroDistribution(b);
  AnyDistribution out;
  lobes.evaluations = 0;
  if (b.basis == Basis::Haar) {
    out = projectLobesHaar(lobes, b.haar, lobes.evaluations);
  } else if (b.basis == Basis::Tetra) {
    out = TetraDistribution::project(lobes, b.tetraLevel);
  } else {
    // Gauss-Legendre nodes enough for a lobe limited to the order (representableExponent).
    out = ShDistribution::project(lobes, b.shOrder, std::max(4 * b.shOrder, 32));
  }
  counts.brdfEvaluations += lobes.evaluations;
  return out;
}

}  // namespace glossy
