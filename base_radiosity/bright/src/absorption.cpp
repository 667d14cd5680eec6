// A scene that cannot absorb has no finite radiosity solution: if every surface reflects all of a
// channel that some emitter emits, and no light leaves the scene or reaches the black back of a
// surface, the light only accumulates. Iterating would run to the iteration limit (a white room at
// rho = 1 stopped after 200 sweeps, 325 s, 87 % of its power unaccounted for), so the solve refuses
// such a scene before it starts, by name.
//
// Whether the light can be absorbed is measured by following it, not inferred from the geometry:
// random walks start on the emitters of the channel and bounce (cosine-distributed) from surface to
// surface; a walk that escapes, reaches a back face or a point under a coplanar cover (the energy
// audit's rules), or lands on a surface that reflects less than all of the channel, shows that
// light can get lost, and the scene is solved. A sealed white box inside a grey room is caught too.
// Only when no walk ends in kWalks x kBounces reflections (the loss per reflection is then below
// 3 / that, 95 % confidence, and the answer at least a hundred thousand times the emission) is the
// scene refused. Emitters reflecting less than all of the channel absorb light that returns to them,
// so the walks run only when every emitter of the channel is white: ordinary scenes pay nothing.
#include <algorithm>
#include <cmath>
#include <string>

#include "solver_state.h"

namespace hr::detail {
namespace {

constexpr int kWalks = 4096, kBounces = 64;

Vec3 cosineDirection(const Vec3& n, Rng& rng) {
  const Vec3 t = std::abs(n.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  const Vec3 u = glm::normalize(glm::cross(t, n)), v = glm::cross(n, u);
  const double phi = 2.0 * kPi * rng.uniform(), r = std::sqrt(rng.uniform());
  return r * std::cos(phi) * u + r * std::sin(phi) * v + std::sqrt(std::max(0.0, 1.0 - r * r)) * n;
}

/// Whether some walk of channel c's light ends (escapes, reaches a back face or a surface that
/// reflects less than all of c). Walks start on the channel's emitters, by area.
bool lightCanBeLost(const SolverState& s, int c) {
  const auto& patches = s.h.patches();
  std::vector<std::uint32_t> emitters;
  std::vector<double> prefix{0.0};
  for (std::uint32_t p = 0; p < patches.size(); ++p)
    if (s.scene.materials[patches[p].material].emission[c] > 0.0) {
      emitters.push_back(p);
      prefix.push_back(prefix.back() + patches[p].area);
    }
  Rng rng(s.opt.seed ^ 0xAB5012Bull, std::uint64_t(c));
  for (int w = 0; w < kWalks; ++w) {
    const double a = (w + rng.uniform()) / kWalks * prefix.back();
    const std::size_t i = std::min<std::size_t>(
        std::size_t(std::upper_bound(prefix.begin(), prefix.end(), a) - prefix.begin()) - 1, emitters.size() - 1);
    std::uint32_t p = emitters[i];
    Vec3 o = patches[p].poly.sample(rng.uniform(), rng.uniform());
    for (int b = 0; b < kBounces; ++b) {
      if (s.vis.coverOf(p, o) != kNone) return true;
      const Vec3 d = cosineDirection(patches[p].normal, rng);
      SurfaceHit hit = s.vis.intersectFrom(o, d, p);
      if (!hit.hit || glm::dot(patches[hit.patch].normal, d) > 0.0) return true;
      p = hit.patch;
      if (s.scene.materials[patches[p].material].diffuse[c] < 1.0) return true;
      o += hit.t * d;
    }
  }
  return false;
}

}  // namespace

void checkCanAbsorb(const SolverState& s) {
  static const char* kChannel[3] = {"red", "green", "blue"};
  const auto& patches = s.h.patches();
  for (int c = 0; c < 3; ++c) {
    bool emits = false, emittersWhite = true;
    for (const Patch& p : patches) {
      const Material& m = s.scene.materials[p.material];
      if (!(m.emission[c] > 0.0)) continue;
      emits = true;
      // Only a Lambertian reflectance of 1 reflects everything: a Phong lobe loses light toward
      // grazing, and rho_d + rho_s <= 1 is enforced, so rho_d = 1 leaves no room for a lobe.
      emittersWhite = emittersWhite && m.diffuse[c] >= 1.0;
    }
    if (!emits || !emittersWhite || lightCanBeLost(s, c)) continue;
    const std::string name = !s.scene.path.empty() ? s.scene.path : !s.scene.name.empty() ? s.scene.name : "(unnamed)";
    throw InputError("scene " + name + " cannot absorb light: none of " + std::to_string(kWalks) +
                     " random walks of its " + kChannel[c] + " light from its emitters was absorbed, escaped or "
                     "reached a back face in " + std::to_string(kBounces) + " reflections, as every surface it "
                     "reaches reflects 100 % of " + kChannel[c] + "; the radiosity has no finite solution "
                     "(lower a reflectance below 1 or open the scene)");
  }
}

}  // namespace hr::detail
