// stats.json: what ran, how long each phase took, what it built, and where the energy went.
#include <hr/output.h>
#include <hr/solve.h>
#include <nlohmann/json.hpp>

#include <malloc.h>

#include <cmath>
#include <cstdio>
#include <cstring>

namespace hr {

namespace {
/// A "Vm...:" line of /proc/self/status, bytes.
std::size_t procStatusBytes(const char* key) {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0;
  char line[256];
  std::size_t kb = 0;
  const std::size_t n = std::strlen(key);
  while (std::fgets(line, sizeof line, f))
    if (std::strncmp(line, key, n) == 0) kb = std::strtoull(line + n, nullptr, 10);
  std::fclose(f);
  return kb * 1024;
}
}  // namespace

std::size_t peakRssBytes() { return procStatusBytes("VmHWM:"); }
std::size_t currentRssBytes() { return procStatusBytes("VmRSS:"); }
std::size_t freeHeapBytes() { return mallinfo2().fordblks; }

std::string statsJson(const RunInfo& run, const SolveStats& st, std::size_t peakRss) {
  using nlohmann::json;
  auto rgb = [](const Rgb& c) { return json::array({c.x, c.y, c.z}); };
  json j;
  j["scene"] = run.scene;
  j["host"] = run.host;
  j["algorithm"] = run.algorithm;
  j["eps"] = run.eps;
  j["max_level"] = run.maxLevel;
  j["threads"] = run.threads;
  j["rays_per_link"] = run.raysPerLink;
  j["seed"] = run.seed;
  j["time_s"] = {{"total", st.tTotal}, {"refine", st.tRefine}, {"visibility", st.tVisibility}, {"gather", st.tGather},
                 {"push_pull", st.tPushPull}, {"energy_check", st.tEnergy}};
  // Per phase: wall and process CPU seconds while it ran, and how many threads did some of its work.
  auto phase = [](const PhaseStat& p) { return json{{"wall_s", p.wall}, {"cpu_s", p.cpu}, {"threads", p.threads}}; };
  j["phases"] = {{"visibility", phase(st.visibility)}, {"refine", phase(st.refine)}, {"gather", phase(st.gather)},
                 {"push_pull", phase(st.pushPull)}, {"energy_check", phase(st.energy)}};
  j["counts"] = {{"initial_patches", st.initialPatches}, {"elements", st.elements}, {"leaves", st.leaves},
                 {"clusters", st.clusters}, {"links", st.links}, {"links_computed", st.linksComputed}, {"rays", st.rays}};
  j["memory_bytes"] = {{"peak_rss", peakRss}, {"links", st.linkBytes}, {"elements", st.elementBytes}};
  Rgb bal = st.emittedW - st.absorbedW - st.escapedW;
  j["energy"] = {{"unit", "W per RGB channel"},
                 {"emitted_w", rgb(st.emittedW)},
                 {"absorbed_w", rgb(st.absorbedW)},
                 {"absorbed_back_faces_w", rgb(st.backAbsorbedW)},
                 {"escaped_w", rgb(st.escapedW)},
                 {"audit_std_error_w", rgb(st.auditStdErrW)},
                 {"imbalance_w", rgb(bal)},
                 {"allowed_imbalance_w", rgb(st.allowedImbalanceW)}};
  // Whether the audit's imbalance is within what the solution may be off by (SolveStats):
  // false means the answer is not trustworthy, and `glossyhr solve` exits 3.
  j["energy_ok"] = st.energyOk;
  j["max_imbalance"] = run.maxImbalance;
  if (!run.extension.empty() || !run.extensionText.empty()) {
    json ext = json::object();
    for (const auto& [name, value] : run.extension) ext[name] = std::isfinite(value) ? json(value) : json(nullptr);
    for (const auto& [name, text] : run.extensionText) ext[name] = text;
    j["extension"] = ext;
  }
  j["iteration_scheme"] = st.iteration == Iteration::Shoot ? "shoot" : "gather";
  j["iterations"] = st.iterations;
  j["converged"] = st.converged;
  j["diverged"] = st.diverged;
  if (st.memoryBudgetBytes > 0)
    j["memory_budget"] = {{"bytes", st.memoryBudgetBytes}, {"eps_reached", st.epsReached},
                          {"coarsest_pass_exceeded", st.memoryBudgetExceeded},
                          {"peak_rss_over_budget", double(peakRss) / double(st.memoryBudgetBytes)}};
  if (st.iteration == Iteration::Shoot) j["unshot_w"] = st.unshotW, j["shoot_fraction"] = st.shootFraction;
  j["samples_peak_per_iteration"] = st.peakSamples;
  j["samples_peak_at_once"] = st.peakSamplesAtOnce;
  // residual_w: gathering, the sweep's power change; shooting, the unshot power left after the pass.
  json hist = json::array();
  for (const auto& h : st.history) {
    json e = {{"iteration", h.iteration}, {"pass", h.pass}, {"residual_w", h.residualW}, {"unconverged_w", h.unconvergedW},
              {"links", h.links}, {"elements", h.elements}, {"links_split", h.refined}, {"samples", h.samples},
              {"seconds", h.seconds}};
    if (st.iteration == Iteration::Shoot)
      e["shooters"] = h.shooters, e["pushed_patches"] = h.pushedPatches, e["samples_at_once"] = h.samplesAtOnce,
      e["reflect_batches"] = h.batches;
    hist.push_back(e);
  }
  j["history"] = hist;
  return j.dump(2) + "\n";
}

void judgeEnergy(SolveStats& st, double maxImbalance) {
  st.allowedImbalanceW = maxImbalance * st.emittedW + 3.0 * st.auditStdErrW;
  for (int c = 0; c < 3; ++c)
    st.energyOk = st.energyOk && std::abs(st.emittedW[c] - st.absorbedW[c] - st.escapedW[c]) <= st.allowedImbalanceW[c];
}

}  // namespace hr
