// Directional bases side by side, in one run: for Phong lobes of exponent 10, 100 and 1000 (rho_s
// 0.8, rho_d 0.1, 30 degrees incidence) and each basis at several levels/orders, the coefficients,
// memory per distribution, projection time, mean evaluation time per direction and the errors against
// the analytic lobe; then the Haar / SH-16 evaluation-time ratio; then the crossovers `--basis auto`
// rests on: each basis at the solve's settings, projected as a solve projects (LobeSpec::asSolved).
#include <glossy/basis_rule.h>
#include <glossy/is_options.h>
#include <glossy/lobe.h>

#include <cstdio>
#include <string>
#include <vector>

namespace {

struct Config {
  std::string name;
  glossy::BasisSpec spec;
};

std::vector<Config> configs() {
  std::vector<Config> c;
  for (double eps : {0.5, 0.2, 0.1})
    for (int maxLevel : {5, 6, 7, 8}) {
      glossy::BasisSpec s;
      s.haar.eps = eps;
      s.haar.maxLevel = maxLevel;
      char name[64];
      std::snprintf(name, sizeof name, "haar eps %.1f max %d", eps, maxLevel);
      c.push_back({name, s});
    }
  for (int level = 2; level <= 6; ++level) {
    glossy::BasisSpec s;
    s.basis = glossy::Basis::Tetra;
    s.tetraLevel = level;
    c.push_back({"tetra level " + std::to_string(level), s});
  }
  for (int order : {4, 8, 12, 16}) {
    glossy::BasisSpec s;
    s.basis = glossy::Basis::Sh;
    s.shOrder = order;
    c.push_back({"sh order " + std::to_string(order), s});
  }
  return c;
}

/// The solve's default settings of each basis and the next finer ones, for the crossover table.
std::vector<Config> solveConfigs() {
  std::vector<Config> c;
  for (int step = 0; step < 2; ++step) {
    glossy::BasisSpec h = glossy::defaultIsBasis(), t = h, s = h;
    h.haar.maxLevel += step;
    t.basis = glossy::Basis::Tetra;
    t.tetraLevel += step;
    s.basis = glossy::Basis::Sh;
    s.shOrder += 4 * step;
    for (const glossy::BasisSpec& b : {h, t, s}) c.push_back({b.describe(), b});
  }
  return c;
}

/// For each exponent and configuration: l2 rel error | coefficients (rho_s 0.5, 30 degrees incidence).
void crossovers() {
  std::printf("\nAs solved (specular lobe only, rho_s 0.5, 30 deg incidence): l2 rel error (coefficients)\n| exponent |");
  for (const Config& c : solveConfigs()) std::printf(" %s |", c.name.c_str());
  std::printf(" auto (defaults) | auto (finer) |\n|---|");
  for (std::size_t k = 0; k < solveConfigs().size() + 2; ++k) std::printf("---|");
  std::printf("\n");
  const glossy::BasisSpec coarse = solveConfigs()[0].spec, fine = solveConfigs()[3].spec;
  glossy::BasisSpec fineAll = fine;
  fineAll.tetraLevel = solveConfigs()[4].spec.tetraLevel;
  fineAll.shOrder = solveConfigs()[5].spec.shOrder;
  for (double n : {2.0, 5.0, 10.0, 15.0, 20.0, 30.0, 40.0, 50.0, 70.0, 100.0, 200.0, 500.0, 1000.0, 5000.0}) {
    glossy::LobeSpec lobe;
    lobe.exponent = n;
    lobe.asSolved = true;
    std::printf("| %g |", n);
    for (const Config& c : solveConfigs()) {
      glossy::LobeReport r = glossy::analyzeLobe(lobe, c.spec, false);
      std::printf(" %.3f (%zu) |", r.l2RelError, r.coefficients);
    }
    std::printf(" %s | %s |\n", glossy::basisName(glossy::autoBasis(n, coarse)), glossy::basisName(glossy::autoBasis(n, fineAll)));
  }
}

}  // namespace

int main(int argc, char** argv) {
  // --crossovers: only the table `--basis auto` rests on (seconds, not minutes).
  if (argc > 1 && std::string(argv[1]) == "--crossovers") {
    crossovers();
    return 0;
  }
  double haarEval = 0.0, sh16Eval = 0.0;
  int haarCount = 0, shCount = 0;
  for (double n : {10.0, 100.0, 1000.0}) {
    glossy::LobeSpec lobe;
    lobe.exponent = n;
    lobe.specular = 0.8;
    lobe.diffuse = 0.1;
    lobe.incidentDeg = 30.0;
    std::printf("\nPhong exponent %g\n", n);
    std::printf("| basis | coefficients | bytes | project ms | eval ns | l2 rel error | max rel error | integral rel error |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    for (const Config& c : configs()) {
      glossy::LobeReport r = glossy::analyzeLobe(lobe, c.spec, true);
      std::printf("| %s | %zu | %zu | %.3f | %.1f | %.4f | %.4f | %.2e |\n", c.name.c_str(), r.coefficients, r.bytes, r.projectMs,
                  r.evalNs, r.l2RelError, r.maxRelError, r.integralRelError);
      if (c.spec.basis == glossy::Basis::Haar) haarEval += r.evalNs, ++haarCount;
      if (c.spec.basis == glossy::Basis::Sh && c.spec.shOrder == 16) sh16Eval += r.evalNs, ++shCount;
    }
  }
  haarEval /= haarCount;
  sh16Eval /= shCount;
  std::printf("\nmean evaluation per direction: Haar (all configurations above) %.1f ns, SH order 16 %.1f ns\n", haarEval, sh16Eval);
  std::printf("ratio Haar / SH-16: %.3f\n", haarEval / sh16Eval);
  crossovers();
  return 0;
}
