// The energy audit's estimators, common to both hosts (hr/audit_estimators.h). The arithmetic is
// written once here so that the two hosts' audits give the same figures for the same rays.
#include <hr/audit_estimators.h>

#include <algorithm>
#include <cmath>

namespace hr::audit {

int raysFor(double p, double sent) {
  const double share = sent > 0.0 ? p / sent : 0.0;
  return std::max(1, static_cast<int>(std::min(1e6, std::ceil(share * kRayBudget))));
}

void tangentFrame(const Vec3& n, Vec3& u, Vec3& v) {
  const Vec3 t = std::abs(n.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  u = glm::normalize(glm::cross(t, n));
  v = glm::cross(n, u);
}

Vec3 latticeCosineDirection(const Vec3& n, const Vec3& u, const Vec3& v, double shift, int k, int M, double jitter) {
  constexpr double kGolden = 0.6180339887498949;
  const double phi = 2.0 * kPi * std::fmod(shift + k * kGolden, 1.0), r = std::sqrt((k + jitter) / M);
  return r * std::cos(phi) * u + r * std::sin(phi) * v + std::sqrt(std::max(0.0, 1.0 - r * r)) * n;
}

void addLambertian(LeafAudit& a, const Rgb& P, const double weight[3], double total) {
  a.escaped += P * (weight[kEscaped] / total);
  a.back += P * (weight[kBack] / total);
  auto var = [&](double m) { return (m + 0.5) * (total - m + 0.5) / ((total + 1.0) * (total + 1.0) * total); };
  a.var += P * P * (var(weight[kEscaped]) + var(weight[kBack]));
}

void addDrawn(LeafAudit& a, const Rgb sum[3], const Rgb sum2[3], double total) {
  a.escaped += sum[kEscaped] / total;
  a.back += sum[kBack] / total;
  for (int f = kEscaped; f <= kBack; ++f)
    a.var += glm::max(Rgb(0.0), sum2[f] / total - (sum[f] / total) * (sum[f] / total)) / total;
}

Totals sum(std::span<const LeafAudit> leaves) {
  Totals t;
  Rgb var(0.0);
  for (const LeafAudit& a : leaves) {
    t.escaped += a.escaped;
    t.back += a.back;
    t.absorbed += a.absorbed + a.back;
    var += a.var;
    t.rays += a.rays;
  }
  t.stdErr = glm::sqrt(var);
  return t;
}

void record(SolveStats& st, const Totals& t, double maxImbalance) {
  st.absorbedW = t.absorbed;
  st.escapedW = t.escaped;
  st.backAbsorbedW = t.back;
  st.auditStdErrW = t.stdErr;
  judgeEnergy(st, maxImbalance);
}

}  // namespace hr::audit
