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

/// What the samples naming a sender normal say about the lamp.
struct LampSamples {
  std::size_t named = 0;      // name a sender normal
  std::size_t wrong = 0;      // of them, another normal than the lamp's, or not facing the receiver
  std::size_t misshapen = 0;  // of them, a shape that is none of the lamp's pieces
  int finest = 0;             // the most halvings of a side seen in a piece
};

/// Checks the recorded samples against the lamp: every normal named is the lamp's (to float rounding),
/// facing the receiver, with a shape (hr/sender_shape.h) that is one of the lamp's pieces: its
/// half-axis along one of the lamp's sides and that side's length over 2^(p + 1), its half-width the
/// other side's over 2^(q + 1), p and q whole (within 1e-4); with `quarters` (pieces split 1 -> 4 only)
/// also p = q.
inline LampSamples samplesNamingTheLamp(const SampleRecorder& r, bool quarters) {
  const hr::Vec3 sides[2] = {hr::Vec3(0, 0, 1), glm::normalize(hr::Vec3(-1, 1, 0))};
  const double lengths[2] = {0.2, 0.2 * std::sqrt(2.0)};
  LampSamples out;
  auto halvings = [](double ratio, int& p) {  // ratio = 2^-p for a whole p >= 0
    const double q = std::round(-std::log2(std::max(ratio, 1e-300)));
    p = int(q);
    return q >= 0.0 && std::abs(ratio * std::exp2(q) - 1.0) <= 1e-4;
  };
  for (const hr::IncidentSample& s : r.seen) {
    if (s.senderNormal == glm::vec3(0.0f)) continue;
    ++out.named;
    const hr::Vec3 n(s.senderNormal), axis(s.senderShape.axis);
    if (glm::length(n - kTiltedLampNormal) > 1e-5 || !(glm::dot(n, s.toSender) < 0.0)) ++out.wrong;
    const double a = glm::length(axis), b = double(s.senderShape.halfWidth);
    int k = -1, p = 0, q = 0;
    for (int i = 0; i < 2; ++i)
      if (a > 0.0 && std::abs(glm::dot(axis / a, sides[i])) > 1.0 - 1e-5) k = i;
    const bool fits = k >= 0 && halvings(2.0 * a / lengths[k], p) && halvings(2.0 * b / lengths[1 - k], q) &&
                      (!quarters || p == q);
    if (!fits) ++out.misshapen;
    out.finest = std::max(out.finest, std::max(p, q));
  }
  return out;
}

}  // namespace testutil
