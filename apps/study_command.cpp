// `glossyhr study`. Each configuration runs as `glossyhr solve` in a child process (its peak RSS is
// its own; a crash or refusal is one row's status, not the sweep's end); images are compared with the
// reference in this process, lights left out. The reference is cached by a hash of the scene file,
// samples, depth and seed, so a second study of the same scene does not trace it again. The path
// tracer's curve uses a different seed than the reference, or its error would be underestimated.
#include "study_command.h"

#include <hr/echo.h>
#include <hr/output.h>
#include <hr/output_set.h>
#include <hr/scene.h>
#include <hr/solution_view.h>
#include <ref/compare.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>


#include "extension_cli.h"
#include "flag_checks.h"
#include "registry.h"
#include "study/child.h"
#include "study/economics.h"
#include "study/grid.h"

namespace fs = std::filesystem;
using nlohmann::json;

const char* kDefaultStudyGrid = "algorithm=diffuse,is;eps=1e-3,3e-4,1e-4;basis=haar,tetra,sh";

namespace {

constexpr hr::limits::Range kViews{"views", 1, 100000};
// The tracer's own curve: images at these sample counts (those above a quarter of the reference's
// are left out: their error would be the reference's noise).
constexpr int kCurveSpp[] = {4, 16, 64, 256};
constexpr long long kReferenceSeed = 1, kCurveSeed = 7919;

study::GridKeys gridKeys() {
  study::GridKeys k;
  k.core = {"eps", "max-level", "rays-per-link", "tolerance", "max-iterations", "seed", "iteration", "shoot-fraction", "host",
            "memory-mb"};
  for (const auto& e : adapters::extensionTable()) {
    std::vector<std::string> opts;
    if (e.make)
      for (const hr::OptionSpec& o : e.make()->options()) opts.push_back(o.name);
    k.byAlgorithm.emplace_back(e.name, opts);
  }
  return k;
}

std::uint64_t fnv1a(const std::string& bytes, std::uint64_t h = 1469598103934665603ull) {
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

fs::path cacheRoot(const StudyArgs& a) {
  if (!a.cache.empty()) return a.cache;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "glossyhr";
  if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".cache" / "glossyhr";
  return fs::temp_directory_path() / "glossyhr-cache";
}

json readJson(const fs::path& p) { return json::parse(readAll(p.string())); }

class Progress {
 public:
  Progress(bool quiet, std::size_t total) : quiet_(quiet), total_(total), t0_(std::chrono::steady_clock::now()) {}
  void step(const std::string& what) {
    ++done_;
    if (quiet_) return;
    double el = elapsed();
    double eta = done_ < total_ ? el / done_ * (total_ - done_) : 0.0;
    std::fprintf(stderr, "study: [%zu/%zu] %s (elapsed %.0f s, about %.0f s left)\n", done_, total_, what.c_str(), el, eta);
  }
  double elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }

 private:
  bool quiet_;
  std::size_t total_, done_ = 0;
  std::chrono::steady_clock::time_point t0_;
};

struct CameraError {
  std::string camera;
  double relRmse = 0, meanRatio = 0;
};

struct Row {
  std::string label, kind, status = "ok";  // kind: solve or path_tracer
  study::Config config;
  int exitCode = 0;
  double seconds = 0, peakRssMb = 0, coefficients = 0, imbalancePct = 0, renderSeconds = 0;
  std::size_t elements = 0, links = 0;
  std::vector<CameraError> errors;
  double meanError() const {
    double s = 0;
    for (const auto& e : errors) s += e.relRmse;
    return errors.empty() ? NAN : s / errors.size();
  }
};

std::vector<CameraError> compareAll(const fs::path& dir, const std::vector<std::string>& cameras,
                                    const std::map<std::string, hr::Image>& reference, const std::vector<std::uint32_t>& lights) {
  std::vector<CameraError> out;
  for (const std::string& c : cameras) {
    ref::Metrics m = ref::compare(hr::readExr((dir / (c + ".exr")).string()), reference.at(c), -1, c, "reference", lights);
    out.push_back({c, m.relRmse, m.meanRatio});
  }
  return out;
}

/// Seconds to render one view of a saved solution, averaged over the cameras (the per-view cost of a
/// walkthrough; loading the solution is paid once and counted with the solve).
double renderSeconds(const fs::path& solution) {
  hr::Solution sol = hr::loadSolution(solution.string());
  hr::SolutionView view(sol);
  std::unique_ptr<hr::Extension> ext = loadExtension(sol, view, solution.string());
  auto t0 = std::chrono::steady_clock::now();
  for (const hr::Camera& cam : sol.cameras) (void)hr::render(sol, cam, ext.get());
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() /
         std::max<std::size_t>(1, sol.cameras.size());
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string num(double v) {
  if (!std::isfinite(v)) return "";
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

}  // namespace

int runStudy(const StudyArgs& a) {
  namespace L = hr::limits;
  if (a.referenceSpp && !a.reference.empty()) throw hr::InputError("--reference-spp and --reference are alternatives: give one");
  checkFlag("--reference-spp", a.referenceSpp, L::kSpp);
  checkFlag("--threads", a.threads, L::kThreads);
  checkFlag("--views", a.views, kViews);
  const std::vector<study::Config> configs = study::parseGrid(a.grid.empty() ? kDefaultStudyGrid : a.grid, gridKeys());
  hr::Scene scene = hr::loadScene(a.scene);
  const std::vector<std::uint32_t> lights = hr::emitterObjects(scene);
  const int threads = a.threads.value_or(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  const int spp = a.referenceSpp.value_or(1024);
  hr::Image given;
  if (!a.reference.empty()) {
    if (scene.cameras.size() != 1)
      throw hr::InputError("--reference: " + a.scene + " has " + std::to_string(scene.cameras.size()) +
                           " cameras; one image is the reference of a one-camera scene only");
    given = hr::readExr(a.reference);
  }
  // The first python3 that has matplotlib: PATH's, else the system's (a virtualenv or pyenv on PATH
  // may lack the Debian package).
  std::string python;
  if (!a.noPlots)
    for (const char* p : {"python3", "/usr/bin/python3"})
      try {
        if (python.empty() && study::run(p, {"-c", "import matplotlib"}, "/dev/null").exitCode == 0) python = p;
      } catch (const std::runtime_error&) {  // not installed there
      }
  if (!a.noPlots && python.empty())
    throw hr::InputError("plots need python3 with matplotlib (Debian: python3-matplotlib); or pass --no-plots");
  std::vector<std::string> names = {"study.csv", "study.json"};
  if (!a.noPlots) names.insert(names.end(), {"error_vs_time.png", "error_vs_memory.png"});
  hr::OutputSet out(a.out, names);
  const study::ScratchDir scratchDir("study");
  const fs::path& scratch = scratchDir.path();
  const std::string T = std::to_string(threads);
  std::size_t curveRuns = 0;
  for (int s : kCurveSpp) curveRuns += 4 * s <= spp;
  Progress progress(a.quiet, configs.size() + curveRuns + (a.reference.empty() ? 1 : 0));

  // The reference: given, cached, or traced now into the cache.
  std::map<std::string, hr::Image> reference;
  std::vector<std::string> cameras;
  json referenceInfo;
  if (!a.reference.empty()) {
    cameras = {scene.cameras.front().name};
    reference[cameras.front()] = given;
    referenceInfo = {{"file", a.reference}};
  } else {
    std::uint64_t key = fnv1a(readAll(a.scene));
    key = fnv1a("spp " + std::to_string(spp) + " seed " + std::to_string(kReferenceSeed), key);
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(key));
    fs::path dir = cacheRoot(a) / ("reference-" + std::string(hex));
    if (!fs::exists(dir / "stats.json")) {
      fs::create_directories(dir.parent_path());
      study::ChildResult r = study::runSelf({"reference", a.scene, "--spp", std::to_string(spp), "--seed",
                                             std::to_string(kReferenceSeed), "--threads", T, "--quiet", "-o", dir.string()},
                                            (scratch / "reference.log").string());
      if (r.exitCode != 0)
        throw std::runtime_error("the reference run failed (exit " + std::to_string(r.exitCode) +
                                 "): " + study::failureReason((scratch / "reference.log").string()));
      progress.step("reference, " + std::to_string(spp) + " spp, cached in " + dir.string());
    } else {
      progress.step("reference, " + std::to_string(spp) + " spp, from the cache " + dir.string());
    }
    referenceInfo = readJson(dir / "stats.json");
    referenceInfo["cache"] = dir.string();
    for (const auto& c : referenceInfo.at("cameras")) {
      cameras.push_back(c.at("name").get<std::string>());
      reference[cameras.back()] = hr::readExr((dir / (cameras.back() + ".exr")).string());
    }
  }

  std::vector<Row> rows;
  std::vector<study::CurvePoint> curve;
  for (int s : kCurveSpp) {
    if (4 * s > spp) continue;
    Row r;
    r.kind = "path_tracer";
    r.label = "path tracer " + std::to_string(s) + " spp";
    r.config = {{"spp", std::to_string(s)}};
    fs::path dir = scratch / ("pt" + std::to_string(s));
    study::ChildResult c = study::runSelf({"reference", a.scene, "--spp", std::to_string(s), "--seed", std::to_string(kCurveSeed),
                                           "--threads", T, "--quiet", "-o", dir.string()},
                                          (scratch / "pt.log").string());
    r.exitCode = c.exitCode;
    if (c.exitCode != 0) {
      r.status = "failed: " + study::failureReason((scratch / "pt.log").string());
    } else {
      json st = readJson(dir / "stats.json");
      for (const auto& cam : st.at("cameras")) r.seconds += cam.at("time_s").get<double>();
      r.seconds /= std::max<std::size_t>(1, st.at("cameras").size());
      r.errors = compareAll(dir, cameras, reference, lights);
      curve.push_back({r.seconds, r.meanError()});
    }
    progress.step(r.label);
    rows.push_back(r);
  }
  const std::optional<study::PowerFit> fit = study::fitPowerLaw(curve);

  for (std::size_t k = 0; k < configs.size(); ++k) {
    Row r;
    r.kind = "solve";
    r.config = configs[k];
    r.label = study::label(configs[k]);
    fs::path dir = scratch / ("c" + std::to_string(k));
    std::vector<std::string> args = {"solve", a.scene};
    for (const auto& [key, v] : configs[k]) args.insert(args.end(), {"--" + key, v});
    args.insert(args.end(), {"--threads", T, "--quiet", "-o", dir.string()});
    std::string log = (scratch / ("c" + std::to_string(k) + ".log")).string();
    study::ChildResult c = study::runSelf(args, log);
    r.exitCode = c.exitCode;
    if (c.exitCode != 0 && c.exitCode != 3) {
      r.status = "failed: " + study::failureReason(log);
    } else {
      if (c.exitCode == 3) r.status = "not trustworthy (exit 3): " + study::failureReason(log);
      json st = readJson(dir / "stats.json");
      r.seconds = st.at("time_s").at("total").get<double>();
      r.peakRssMb = st.at("memory_bytes").at("peak_rss").get<double>() / (1024.0 * 1024.0);
      r.elements = st.at("counts").at("elements").get<std::size_t>();
      r.links = st.at("counts").at("links").get<std::size_t>();
      if (st.contains("extension") && st["extension"].contains("coefficients_total"))
        r.coefficients = st["extension"]["coefficients_total"].get<double>();
      const auto& e = st.at("energy");
      double emitted = e.at("emitted_w")[1].get<double>();
      r.imbalancePct = emitted > 0 ? 100.0 * e.at("imbalance_w")[1].get<double>() / emitted : 0.0;
      r.errors = compareAll(dir, cameras, reference, lights);
      r.renderSeconds = renderSeconds(dir / "solution.ghrs");
    }
    progress.step(r.label + (r.status == "ok" ? "" : " -- " + r.status));
    rows.push_back(r);
  }

  // study.csv: one row per configuration and camera; the walkthrough columns per configuration.
  const int views = a.views.value_or(10);
  std::vector<std::string> keys;
  for (const auto& c : configs)
    for (const auto& [key, v] : c)
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  std::ostringstream csv;
  csv << "kind,label";
  for (const auto& key : keys) csv << "," << key;
  csv << ",spp,status,exit_code,camera,seconds,peak_rss_mb,coefficients,elements,links,imbalance_pct,rel_rmse,mean_ratio,"
         "render_s,tracer_s_at_equal_error,break_even_views,ratio_at_"
      << views << "_views\n";
  json jrows = json::array();
  for (const Row& r : rows) {
    json jr = {{"kind", r.kind}, {"label", r.label}, {"status", r.status}, {"exit_code", r.exitCode}};
    for (const auto& [key, v] : r.config) jr["config"][key] = v;
    std::optional<study::Economics> eco;
    if (r.kind == "solve" && fit && !r.errors.empty() && r.meanError() > 0)
      eco = study::economics(*fit, r.meanError(), r.seconds, r.renderSeconds, views);
    auto field = [&](auto v) { return r.status.rfind("failed", 0) == 0 ? std::string() : num(v); };
    std::vector<CameraError> errs = r.errors.empty() ? std::vector<CameraError>{{"", NAN, NAN}} : r.errors;
    for (const CameraError& e : errs) {
      csv << r.kind << "," << csvField(r.label);
      for (const auto& key : keys) csv << "," << csvField(study::value(r.config, key));
      csv << "," << csvField(study::value(r.config, "spp")) << "," << csvField(r.status) << "," << r.exitCode << ","
          << csvField(e.camera) << "," << field(r.seconds) << "," << (r.kind == "solve" ? field(r.peakRssMb) : "") << ","
          << (r.kind == "solve" ? field(r.coefficients) : "") << ","
          << (r.kind == "solve" ? field(double(r.elements)) : "") << "," << (r.kind == "solve" ? field(double(r.links)) : "")
          << "," << (r.kind == "solve" ? field(r.imbalancePct) : "") << "," << num(e.relRmse) << "," << num(e.meanRatio) << ","
          << (r.kind == "solve" ? field(r.renderSeconds) : "") << "," << (eco ? num(eco->tracerSecondsPerImage) : "") << ","
          << (eco && eco->breakEvenViews ? num(*eco->breakEvenViews) : eco ? "never" : "") << ","
          << (eco ? num(eco->ratioAtViews) : "") << "\n";
    }
    if (r.status.rfind("failed", 0) != 0) {
      jr["seconds"] = r.seconds;
      if (r.kind == "solve")
        jr.update({{"peak_rss_mb", r.peakRssMb}, {"coefficients", r.coefficients}, {"elements", r.elements},
                   {"links", r.links}, {"imbalance_pct", r.imbalancePct}, {"render_s", r.renderSeconds}});
      for (const auto& e : r.errors) jr["cameras"][e.camera] = {{"rel_rmse", e.relRmse}, {"mean_ratio", e.meanRatio}};
    }
    if (eco) {
      jr["walkthrough"] = {{"tracer_s_at_equal_error", eco->tracerSecondsPerImage},
                           {"break_even_views", eco->breakEvenViews ? json(*eco->breakEvenViews) : json("never")},
                           {"views", views},
                           {"ratio_at_views", eco->ratioAtViews}};
    }
    jrows.push_back(jr);
  }
  json doc = {{"scene", a.scene},
              {"grid", a.grid.empty() ? kDefaultStudyGrid : a.grid},
              {"threads", threads},
              {"units", "seconds wall time; peak RSS MiB; rel_rmse of luminance against the reference, lights left out"},
              {"reference", referenceInfo},
              {"rows", jrows}};
  if (fit) doc["tracer_fit"] = {{"log_error_intercept", fit->a}, {"log_error_slope_per_log_second", fit->b}};
  hr::writeFileAtomically(out.path("study.csv"), csv.str());
  hr::writeFileAtomically(out.path("study.json"), doc.dump(2) + "\n");
  if (!a.noPlots) {
    std::string log = (scratch / "plot.log").string();
    if (study::run(python, {GHR_STUDY_PLOT, out.path("study.csv"), out.path("error_vs_time.png"), out.path("error_vs_memory.png")},
                   log).exitCode != 0)
      throw std::runtime_error("plotting failed: " + study::failureReason(log));
  }
  out.commit();

  std::size_t failed = 0;
  for (const Row& r : rows) failed += r.status != "ok";
  if (!a.quiet) {
    std::fprintf(stderr, "\nsummary: %zu configurations and %zu path-tracer runs in %.0f s, %zu not ok\n", configs.size(),
                 curveRuns, progress.elapsed(), failed);
    for (const Row& r : rows)
      std::fprintf(stderr, "  %-48s %8.2f s  rel. RMSE %s  %s\n", r.label.c_str(), r.seconds, num(r.meanError()).c_str(),
                   r.status.c_str());
  }
  std::printf("outputs in %s:\n", fs::absolute(a.out).string().c_str());
  for (const auto& w : out.finalPaths()) std::printf("  %s\n", w.c_str());
  return 0;
}
