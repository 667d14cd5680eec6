// The lobe inspection command: validation of every option against the chosen basis, the report as
// text or JSON (keys: coefficients, bytes, project_ms, eval_ns, l2_rel_error, max_rel_error,
// integral_rel_error), and the lobe as a VTK surface whose radius and colour are the projected value.
#include "lobe_command.h"

#include "lobe_surface.h"

#include <glossy/lobe.h>
#include <hr/output.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

namespace {

void require(bool ok, const std::string& message) {
  if (!ok) throw hr::InputError(message);
}

glossy::BasisSpec basisFrom(const LobeArgs& a) {
  glossy::BasisSpec b;
  try {
    b.basis = glossy::parseBasis(a.basis);
  } catch (const std::invalid_argument& e) {
    throw hr::InputError(std::string("--basis: ") + e.what());
  }
  const bool haar = b.basis == glossy::Basis::Haar, tetra = b.basis == glossy::Basis::Tetra, sh = b.basis == glossy::Basis::Sh;
  require(haar || (!a.eps && !a.minLevel && !a.maxLevel && !a.floor && a.refiner == "relative" && !a.noHints),
          "--eps, --min-level, --max-level, --refiner, --floor and --no-hints apply to --basis haar");
  require(tetra || !a.level, "--level applies to --basis tetra");
  require(sh || (!a.order && !a.quadrature), "--order and --quadrature apply to --basis sh");
  if (haar) {
    if (a.refiner == "absolute")
      b.haar.refiner = glossy::Refiner::Absolute;
    else
      require(a.refiner == "relative", "--refiner: '" + a.refiner + "' is neither relative nor absolute");
    b.haar.eps = a.eps.value_or(b.haar.eps);
    b.haar.floor = a.floor.value_or(b.haar.floor);
    b.haar.minLevel = a.minLevel.value_or(b.haar.minLevel);
    b.haar.maxLevel = a.maxLevel.value_or(b.haar.maxLevel);
    require(b.haar.eps > 0.0 && std::isfinite(b.haar.eps), "--eps must be a positive number");
    require(b.haar.floor >= 0.0 && b.haar.floor <= 1.0, "--floor: a fraction of the peak in [0, 1]");
    require(b.haar.minLevel >= 0, "--min-level must be >= 0");
    require(b.haar.maxLevel <= 12, "--max-level: at most 12 (8 * 4^12 cells)");
    require(b.haar.minLevel <= b.haar.maxLevel, "--min-level must not exceed --max-level (" + std::to_string(b.haar.maxLevel) + ")");
  }
  if (tetra) {
    b.tetraLevel = a.level.value_or(b.tetraLevel);
    require(b.tetraLevel >= 0 && b.tetraLevel <= glossy::TetraMesh::kMaxLevel, "--level: 0 to " + std::to_string(glossy::TetraMesh::kMaxLevel));
  }
  if (sh) {
    b.shOrder = a.order.value_or(b.shOrder);
    b.shQuadrature = a.quadrature.value_or(b.shQuadrature);
    require(b.shOrder >= 1 && b.shOrder <= glossy::ShDistribution::kMaxOrder,
            "--order: 1 to " + std::to_string(glossy::ShDistribution::kMaxOrder));
    require(!a.quadrature || *a.quadrature >= b.shOrder, "--quadrature: at least the order");
  }
  return b;
}

}  // namespace

int runLobe(const LobeArgs& a) {
  require(std::isfinite(a.exponent) && a.exponent >= 0.0, "--exponent must be a number >= 0");
  require(std::isfinite(a.specular) && std::isfinite(a.diffuse) && a.specular >= 0.0 && a.diffuse >= 0.0,
          "--specular and --diffuse must be >= 0 (no negative reflectance)");
  require(a.specular + a.diffuse <= 1.0, "--specular + --diffuse must not exceed 1 (the material would gain energy)");
  require(std::isfinite(a.incidentDeg) && a.incidentDeg >= 0.0 && a.incidentDeg < 90.0, "--incident-deg: 0 <= angle from the normal < 90");
  require(std::isfinite(a.azimuthDeg), "--azimuth-deg must be a number");
  require(a.out.empty() || (a.out.size() > 4 && a.out.substr(a.out.size() - 4) == ".vtp"), "-o: the lobe file must end in .vtp");
  glossy::BasisSpec basis = basisFrom(a);
  glossy::LobeSpec spec;
  spec.exponent = a.exponent;
  spec.specular = a.specular;
  spec.diffuse = a.diffuse;
  spec.incidentDeg = a.incidentDeg;
  spec.azimuthDeg = a.azimuthDeg;
  spec.hints = !a.noHints;
  glossy::AnyDistribution d;
  glossy::LobeReport r = glossy::analyzeLobe(spec, basis, true, &d);
  if (!a.out.empty()) {
    glossy::Lobe analytic(spec);
    writeLobeSurface(a.out, {{"intensity", [&](const hr::Vec3& v) { return glossy::eval(d, v); }},
                             {"analytic_intensity", [&](const hr::Vec3& v) { return analytic(v); }}});
  }
  if (a.json) {
    nlohmann::json j;
    j["basis"] = basis.describe();
    j["lobe"] = {{"exponent", a.exponent}, {"specular", a.specular}, {"diffuse", a.diffuse},
                 {"incident_deg", a.incidentDeg}, {"azimuth_deg", a.azimuthDeg}};
    if (basis.basis == glossy::Basis::Haar) j["peak_hints"] = spec.hints;
    j["units"] = "intensity in W/sr per (W/m^2 of irradiance x m^2 of area); integral in W per W";
    j["coefficients"] = r.coefficients;
    j["bytes"] = r.bytes;
    j["project_ms"] = r.projectMs;
    j["eval_ns"] = r.evalNs;
    j["l2_rel_error"] = r.l2RelError;
    j["max_rel_error"] = r.maxRelError;
    j["integral_rel_error"] = r.integralRelError;
    j["integral"] = r.integral;
    j["analytic_integral"] = r.analyticIntegral;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("lobe: Phong n = %g, rho_s = %g, rho_d = %g, incidence %g deg; basis: %s%s\n", a.exponent, a.specular,
                a.diffuse, a.incidentDeg, basis.describe().c_str(),
                basis.basis == glossy::Basis::Haar ? (spec.hints ? ", peak hints" : ", no hints") : "");
    std::printf("  coefficients        %zu\n", r.coefficients);
    std::printf("  bytes               %zu\n", r.bytes);
    std::printf("  project_ms          %.4f\n", r.projectMs);
    std::printf("  eval_ns             %.1f   (mean per direction)\n", r.evalNs);
    std::printf("  l2_rel_error        %.4g\n", r.l2RelError);
    std::printf("  max_rel_error       %.4g   (relative to the lobe's peak)\n", r.maxRelError);
    std::printf("  integral_rel_error  %.4g   (projected %.6g vs analytic %.6g W/W)\n", r.integralRelError, r.integral,
                r.analyticIntegral);
    if (!a.out.empty()) std::printf("  lobe surface        %s\n", a.out.c_str());
  }
  return 0;
}
