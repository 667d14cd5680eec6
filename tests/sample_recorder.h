// An extension that only watches: it simulates the materials with a specular part, reflects
// nothing, and records every Illumination Sample a host hands it (gathering or shooting). The hosts'
// tests read what their samples say about their senders.
#pragma once
#include <hr/extension.h>

#include <cmath>
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
/// is the lamp's (to float rounding), facing the receiver, with a shape (hr/sender_shape.h) that is
/// one of the lamp's pieces: its half-axis along one of the lamp's sides and in its plane, and its
/// area the lamp's over a power of two (pieces split 1 -> 4 or 1 -> 2), within 1e-4. Returns how many
/// named it; *wrong counts those with another normal, *misshapen those with another shape.
inline std::size_t samplesNamingTheLamp(const SampleRecorder& r, std::size_t* wrong, std::size_t* misshapen) {
  const hr::Vec3 sides[2] = {hr::Vec3(0, 0, 1), glm::normalize(hr::Vec3(-1, 1, 0))};
  const double lampArea = 0.2 * 0.2 * std::sqrt(2.0);
  std::size_t named = 0;
  *wrong = 0;
  *misshapen = 0;
  for (const hr::IncidentSample& s : r.seen) {
    if (s.senderNormal == glm::vec3(0.0f)) continue;
    ++named;
    const hr::Vec3 n(s.senderNormal);
    if (glm::length(n - kTiltedLampNormal) > 1e-5 || !(glm::dot(n, s.toSender) < 0.0)) ++*wrong;
    const hr::Vec3 axis(s.senderShape.axis);
    const double a = glm::length(axis), area = 4.0 * a * double(s.senderShape.halfWidth);
    const double pieces = a > 0.0 ? lampArea / area : 0.0;
    const double power = std::round(std::log2(std::max(pieces, 1e-300)));
    auto along = [&](const hr::Vec3& side) {
      return a > 0.0 && std::abs(glm::dot(axis / a, side)) > 1.0 - 1e-5;
    };
    const bool alongSide = along(sides[0]) || along(sides[1]);
    if ((!alongSide || !(power >= 0.0) || std::abs(pieces / std::exp2(power) - 1.0) > 1e-4)) ++*misshapen;
  }
  return named;
}

}  // namespace testutil
