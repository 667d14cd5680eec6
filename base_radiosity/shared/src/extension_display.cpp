// Display vertices of an extension's leaves and their per-eye evaluation (see extension_display.h).
#include <hr/extension_display.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <map>
#include <tuple>

namespace hr {

ExtensionDisplay::ExtensionDisplay(const Solution& s, const Extension& ext) : s_(s), ext_(ext) {
  std::vector<char> sim(s.materials.size(), 0);
  for (std::size_t m = 0; m < s.materials.size(); ++m) {
    const Material& mt = s.materials[m];
    sim[m] = ext.simulates({mt.diffuse, mt.specular, mt.exponent, mt.emission}) ? 1 : 0;
  }
  Aabb box;
  for (const Patch& p : s.patches)
    for (int k = 0; k < p.poly.n; ++k) box.grow(p.poly.v[k]);
  const double q = std::max(box.diagonal(), 1e-300) * 1e-7;
  // Vertices keyed by quantised position, object and material; members in leaf order.
  using Key = std::tuple<std::int64_t, std::int64_t, std::int64_t, std::uint32_t, std::uint32_t>;
  std::map<Key, std::uint32_t> index;
  std::vector<std::vector<std::uint32_t>> members;  // per vertex: the leaves meeting there
  cornerOf_.assign(s.elements.size(), kNone);
  for (std::uint32_t i = 0; i < s.elements.size(); ++i) {
    const SolutionElement& e = s.elements[i];
    const Patch& p = s.patches[e.patch];
    if (!e.leaf() || !sim[p.material]) continue;
    cornerOf_[i] = static_cast<std::uint32_t>(cornerVertex_.size());
    for (int k = 0; k < 4; ++k) {
      const Vec3& v = e.poly.v[k < e.poly.n ? k : e.poly.n - 1];
      Key key{std::llround(v.x / q), std::llround(v.y / q), std::llround(v.z / q), p.object, p.material};
      auto [it, fresh] = index.emplace(key, static_cast<std::uint32_t>(pos_.size()));
      if (fresh) {
        pos_.push_back(v);
        members.emplace_back();
      }
      if (k < e.poly.n && (members[it->second].empty() || members[it->second].back() != i)) members[it->second].push_back(i);
      cornerVertex_.push_back(it->second);
    }
  }
  memberStart_.assign(1, 0);
  for (std::size_t v = 0; v < members.size(); ++v) {
    member_.insert(member_.end(), members[v].begin(), members[v].end());
    memberStart_.push_back(static_cast<std::uint32_t>(member_.size()));
  }
  // Each corner averages the members whose normal is within 30 degrees of its leaf's: creases of one
  // object (a box's edges) stay sharp, a tessellated sphere is smooth.
  const double cosMax = std::cos(30.0 * kPi / 180.0);
  useStart_.assign(1, 0);
  for (std::uint32_t i = 0; i < s.elements.size(); ++i) {
    if (cornerOf_[i] == kNone) continue;
    const Vec3& n = s.patches[s.elements[i].patch].normal;
    for (int k = 0; k < 4; ++k) {
      std::uint32_t v = cornerVertex_[cornerOf_[i] + k];
      for (std::uint32_t m = memberStart_[v]; m < memberStart_[v + 1]; ++m)
        if (glm::dot(s.patches[s.elements[member_[m]].patch].normal, n) >= cosMax) use_.push_back(m);
      useStart_.push_back(static_cast<std::uint32_t>(use_.size()));
    }
  }
  memberArea_.resize(member_.size());
  for (std::size_t m = 0; m < member_.size(); ++m) memberArea_[m] = s.elements[member_[m]].poly.area();
  // A vertex of a curved object the solution knows (Solution::surfaces) is shaded at its surface's
  // normal. Elsewhere, a vertex whose leaves all face within 30 degrees of each other, not all the
  // same way, lies on a curved surface: its shading normal is their area-weighted mean, which leans
  // toward the larger of adaptively refined cells (on floor_gloss's sphere that moved the highlight
  // by a fifth of a degree). A crease or a plane has none.
  normal_.assign(pos_.size(), Vec3(0.0));
  for (std::size_t v = 0; v < pos_.size(); ++v) {
    const Vec3 exact = surfaceNormal(s, s.elements[member_[memberStart_[v]]].patch, pos_[v]);
    if (exact != Vec3(0.0)) {
      normal_[v] = exact;
      continue;
    }
    Vec3 sum(0.0);
    bool smooth = true, turned = false;
    for (std::uint32_t a = memberStart_[v]; a < memberStart_[v + 1] && smooth; ++a) {
      const Vec3& na = s.patches[s.elements[member_[a]].patch].normal;
      sum += memberArea_[a] * na;
      for (std::uint32_t b = a + 1; b < memberStart_[v + 1]; ++b) {
        double c = glm::dot(na, s.patches[s.elements[member_[b]].patch].normal);
        smooth = smooth && c >= cosMax;
        turned = turned || c < 1.0 - 1e-9;
      }
    }
    const double len = glm::length(sum);
    if (smooth && turned && len > 0.0 && allFinite(sum)) normal_[v] = sum / len;
  }
  curved_.assign(s.elements.size(), 0);
  for (std::uint32_t i = 0; i < s.elements.size(); ++i)
    for (int k = 0; k < 4 && cornerOf_[i] != kNone; ++k) curved_[i] |= normal_[cornerVertex_[cornerOf_[i] + k]] != Vec3(0.0) ? 1 : 0;
  value_.assign(member_.size(), Rgb(0.0));
  cornerValue_.assign(cornerVertex_.size(), Rgb(0.0));
}

std::size_t ExtensionDisplay::update(const Vec3& eye, double thresholdDeg) {
  // A vertex is due when it was never evaluated or its direction turned by more than the threshold;
  // a threshold of 0 makes every vertex due (the still images' path, exactly as before thresholds).
  const bool all = !(thresholdDeg > 0.0);
  const float cosMin = static_cast<float>(std::cos(std::min(thresholdDeg, 180.0) * kPi / 180.0));
  if (lastDir_.size() != pos_.size()) lastDir_.assign(pos_.size(), glm::vec3(0.0f));
  fresh_.assign(pos_.size(), 0);
  std::atomic<std::size_t> updated{0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pos_.size(), 256), [&](const auto& r) {
    std::size_t count = 0;
    for (std::size_t v = r.begin(); v != r.end(); ++v) {
      Vec3 d = eye - pos_[v];
      double len = glm::length(d);
      d = len > 0.0 ? d / len : Vec3(0, 0, 1);
      const glm::vec3 df(d);
      if (!all && lastDir_[v] != glm::vec3(0.0f) && glm::dot(df, lastDir_[v]) >= cosMin) continue;
      lastDir_[v] = df;
      fresh_[v] = 1;
      ++count;
      for (std::uint32_t m = memberStart_[v]; m < memberStart_[v + 1]; ++m) {
        const Vec3& n = normal_[v];
        Rgb L = n != Vec3(0.0) ? ext_.radiance(NodeId{member_[m]}, d, n) : ext_.radiance(NodeId{member_[m]}, d);
        value_[m] = allFinite(L) ? glm::max(L, Rgb(0.0)) : Rgb(0.0);
      }
    }
    updated += count;
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cornerValue_.size(), 1024), [&](const auto& r) {
    for (std::size_t c = r.begin(); c != r.end(); ++c) {
      if (!fresh_[cornerVertex_[c]]) continue;
      Rgb sum(0.0);
      double w = 0.0;
      for (std::uint32_t u = useStart_[c]; u < useStart_[c + 1]; ++u) {
        double a = memberArea_[use_[u]];
        sum += a * value_[use_[u]];
        w += a;
      }
      cornerValue_[c] = w > 0.0 ? sum / w : Rgb(0.0);
    }
  });
  return updated.load();
}

Rgb ExtensionDisplay::radiance(std::uint32_t leaf, const Vec3& x) const {
  if (leaf >= cornerOf_.size() || cornerOf_[leaf] == kNone) return Rgb(0.0);
  const std::uint32_t c = cornerOf_[leaf];
  return interpolateCorners(s_, leaf, x, {cornerValue_[c], cornerValue_[c + 1], cornerValue_[c + 2], cornerValue_[c + 3]});
}

Rgb ExtensionDisplay::radiance(std::uint32_t leaf, const Vec3& x, const Vec3& toEye) const {
  if (leaf >= cornerOf_.size() || cornerOf_[leaf] == kNone) return Rgb(0.0);
  if (!curved_[leaf]) return radiance(leaf, x);
  const std::uint32_t c = cornerOf_[leaf];
  const std::array<double, 4> w = cornerWeights(s_, leaf, x);
  const Vec3& own = s_.patches[s_.elements[leaf].patch].normal;
  // The surface's own point and normal where the solution knows the surface (the ray met a facet
  // or a display cell, a chord of it); else the corners' interpolated normal at x.
  const std::uint32_t object = s_.patches[s_.elements[leaf].patch].object;
  const Vec3 at = object < s_.surfaces.size() ? s_.surfaces[object].meet(x, toEye) : x;
  Vec3 n = surfaceNormal(s_, s_.elements[leaf].patch, at);
  if (n == Vec3(0.0)) {
    for (std::uint32_t k = 0; k < 4; ++k) {
      const Vec3& nv = normal_[cornerVertex_[c + k]];
      n += w[k] * (nv != Vec3(0.0) ? nv : own);
    }
    const double len = glm::length(n);
    n = len > 0.0 && allFinite(n) ? n / len : own;
  }
  Rgb out(0.0);
  for (std::uint32_t k = 0; k < 4; ++k) {
    if (!(w[k] > 0.0)) continue;
    Rgb sum(0.0);
    double a = 0.0;
    for (std::uint32_t u = useStart_[c + k]; u < useStart_[c + k + 1]; ++u) {
      Rgb L = ext_.radiance(NodeId{member_[use_[u]]}, toEye, n, at);
      sum += memberArea_[use_[u]] * (allFinite(L) ? glm::max(L, Rgb(0.0)) : Rgb(0.0));
      a += memberArea_[use_[u]];
    }
    if (a > 0.0) out += w[k] * (sum / a);
  }
  return out;
}

}  // namespace hr
