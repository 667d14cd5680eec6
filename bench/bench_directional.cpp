// Directional bases side by side, in one run: for Phong lobes of exponent 10, 100 and 1000 (rho_s
// 0.8, rho_d 0.1, 30 degrees incidence) and each basis at several levels/orders, the coefficients,
// memory per distribution, projection time, mean evaluation time per direction and the errors against
// the analytic lobe; then the Haar / SH-16 evaluation-time ratio.
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

}  // namespace

int main() {
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
  return 0;
}
