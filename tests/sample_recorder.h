// An extension that only watches: it simulates the materials with a specular part, reflects
// nothing, and records every Illumination Sample a host hands it (gathering or shooting). The hosts'
// tests read what their samples say about their senders.
#pragma once
#include <hr/extension.h>

#include <mutex>
#include <vector>

namespace testutil {

class SampleRecorder final : public hr::Extension {
 public:
  std::string_view name() const override { return "recorder"; }
  bool simulates(const hr::MaterialInfo& m) const override { return m.specular.y > 0.0; }
  bool canShoot() const override { return true; }
  void reflect(hr::NodeId, std::span<const hr::IncidentSample> s) override { keep(s); }
  void reflectShot(hr::NodeId, std::span<const hr::IncidentSample> s) override { keep(s); }
  std::vector<hr::IncidentSample> seen;

 private:
  void keep(std::span<const hr::IncidentSample> s) {
    std::lock_guard<std::mutex> lock(m_);
    seen.insert(seen.end(), s.begin(), s.end());
  }
  std::mutex m_;
};

/// A tilted 20 x 28 cm lamp 1 m above a 2 x 2 m glossy floor (the lamp faces down and toward -x) and
/// nothing else: every sample the floor receives comes from the lamp, whose normal is kTiltedLampNormal.
inline const char* kTiltedLampOverGlossyFloor = R"({
  "materials": { "floor": { "diffuse": [0.3,0.3,0.3], "specular": [0.5,0.5,0.5], "exponent": 100 },
                 "lamp": { "diffuse": [0,0,0], "emission": [20,20,20] } },
  "objects": [
    { "type": "quad", "material": "floor", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]] },
    { "type": "quad", "material": "lamp", "vertices": [[0.1,0.9,-0.1],[0.1,0.9,0.1],[-0.1,1.1,0.1],[-0.1,1.1,-0.1]] } ] })";
inline const hr::Vec3 kTiltedLampNormal = glm::normalize(hr::Vec3(-1.0, -1.0, 0.0));

/// Checks the recorded samples against the lamp: some name a sender normal, and every normal named
/// is the lamp's (to float rounding), facing the receiver. Returns how many named it.
inline std::size_t samplesNamingTheLamp(const SampleRecorder& r, std::size_t* wrong) {
  std::size_t named = 0;
  *wrong = 0;
  for (const hr::IncidentSample& s : r.seen) {
    if (s.senderNormal == glm::vec3(0.0f)) continue;
    ++named;
    const hr::Vec3 n(s.senderNormal);
    if (glm::length(n - kTiltedLampNormal) > 1e-5 || !(glm::dot(n, s.toSender) < 0.0)) ++*wrong;
  }
  return named;
}

}  // namespace testutil
