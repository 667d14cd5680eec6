// The reference and compare commands. Input is validated before the output folder is touched; the
// files of a run are written as one set (hr/output_set.h). compare refuses images it cannot measure
// against (non-finite pixels, an all-black reference) instead of reporting a misleading 0.
#include "reference_command.h"

#include <hr/auto_camera.h>
#include <hr/output_set.h>
#include <ref/compare.h>
#include <ref/path_tracer.h>
#include <tbb/global_control.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

#include "flag_checks.h"

namespace fs = std::filesystem;

int runReference(const ReferenceArgs& a) {
  namespace L = hr::limits;
  if (a.spp && a.timeS) throw hr::InputError("--spp and --time-s are alternatives: give one");
  checkFlag("--spp", a.spp, L::kSpp);
  checkFlag("--time-s", a.timeS, L::kTimeS);
  checkFlag("--max-depth", std::optional<int>(a.maxDepth), L::kMaxDepth);
  checkFlag("--threads", a.threads, L::kThreads);
  checkFlag("--seed", std::optional<long long>(a.seed), L::kSeed);
  hr::Progress progress(a.quiet);
  progress.phase("loading scene");
  hr::Scene scene = a.scene.empty() ? hr::defaultScene() : hr::loadScene(a.scene);
  for (const auto& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  for (const auto& d : scene.dropped) std::fprintf(stderr, "note: dropped or approximated: %s\n", d.c_str());
  int threads = a.threads ? *a.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  hr::TessellationReport rep;
  std::vector<hr::Patch> patches = hr::buildPatches(scene, rep);
  if (rep.droppedZeroArea) std::fprintf(stderr, "warning: dropped %zu zero-area face(s)\n", rep.droppedZeroArea);
  if (scene.cameras.empty()) {
    hr::Visibility probe(patches);  // the solver's hosts choose with the same rule
    scene.cameras.push_back(hr::autoCamera(scene, patches, probe));
  }
  std::vector<std::string> names;
  for (const hr::Camera& c : scene.cameras) names.insert(names.end(), {c.name + ".exr", c.name + ".png", c.name + ".var.exr"});
  names.push_back("stats.json");
  hr::OutputSet out(a.out, names);
  ref::PathTracer pt(scene, std::move(patches));
  ref::Options o;
  o.spp = a.spp.value_or(64);
  o.timeS = a.timeS.value_or(0.0);
  o.maxDepth = a.maxDepth;
  o.seed = static_cast<std::uint64_t>(a.seed);

  std::vector<std::pair<hr::Camera, ref::CameraResult>> results;
  for (const hr::Camera& cam : scene.cameras) {
    progress.phase("path tracing camera \"" + cam.name + "\"");
    results.emplace_back(cam, pt.render(cam, o, &progress));
  }
  progress.phase("writing outputs");
  nlohmann::json stats;
  stats["scene"] = a.scene.empty() ? "built-in:cornell_box" : a.scene;
  stats["algorithm"] = "path tracing, next-event estimation + BRDF sampling (MIS, power heuristic), Russian roulette";
  stats["max_depth"] = a.maxDepth;
  stats["seed"] = a.seed;
  stats["threads"] = threads;
  stats["units"] = "radiance W/(m^2 sr); variance of the pixel mean (W/(m^2 sr))^2";
  nlohmann::json cams = nlohmann::json::array();
  for (auto& [cam, r] : results) {
    hr::writeExr(r.image, out.path(cam.name + ".exr"));
    hr::writePng(r.image, out.path(cam.name + ".png"));
    hr::Image var = r.image;
    var.rgb = r.variance;
    hr::writeExr(var, out.path(cam.name + ".var.exr"));
    cams.push_back({{"name", cam.name},
                    {"width", cam.width},
                    {"height", cam.height},
                    {"spp", r.spp},
                    {"time_s", r.seconds},
                    {"cpu_s", r.cpuSeconds},
                    {"paths", r.paths},
                    {"paths_per_s", r.seconds > 0 ? double(r.paths) / r.seconds : 0.0},
                    {"image_mean_luminance", r.meanLuminance},
                    {"rel_std_error_of_mean", r.relStdError},
                    {"non_finite_samples", r.nonFinite}});
    if (!a.quiet)
      std::fprintf(stderr, "camera \"%s\": %d spp in %.2f s (%.3g paths/s), image mean %.4g W/(m^2 sr) +- %.2g %%\n",
                   cam.name.c_str(), r.spp, r.seconds, r.seconds > 0 ? double(r.paths) / r.seconds : 0.0, r.meanLuminance,
                   100.0 * r.relStdError);
  }
  stats["cameras"] = cams;
  hr::writeFileAtomically(out.path("stats.json"), stats.dump(2) + "\n");
  out.commit();
  std::printf("outputs in %s:\n", fs::absolute(a.out).string().c_str());
  for (const auto& w : out.finalPaths()) std::printf("  %s\n", w.c_str());
  return 0;
}

int runCompare(const CompareArgs& a) {
  if (!a.out.empty() && fs::path(a.out).extension() != ".png") throw hr::InputError("-o: the difference image must end in .png");
  checkFlag("--mask", a.mask, hr::limits::kObjectId);
  const long mask = a.mask ? static_cast<long>(*a.mask) : -1;
  std::vector<std::uint32_t> exclude;
  for (long long id : a.exclude) {
    checkFlag("--exclude", std::optional<long long>(id), hr::limits::kObjectId);
    exclude.push_back(static_cast<std::uint32_t>(id));
  }
  if (!a.lightsOf.empty()) {
    hr::Scene scene = hr::loadScene(a.lightsOf);  // names the file and key when it cannot be read
    std::vector<std::uint32_t> lights = hr::emitterObjects(scene);
    exclude.insert(exclude.end(), lights.begin(), lights.end());
  }
  hr::Image A = hr::readExr(a.a), B = hr::readExr(a.b);
  ref::Metrics m = ref::compare(A, B, mask, a.a, a.b, exclude);
  if (!a.variance.empty()) ref::addReferenceNoise(m, A, B, hr::readExr(a.variance), mask, exclude, a.variance);
  if (!a.out.empty()) ref::writeDifferencePng(A, B, a.out, mask, 0.25, exclude);
  if (a.json) {
    nlohmann::json j = {{"a", a.a},
                        {"b", a.b},
                        {"pixels", m.pixels},
                        {"rel_rmse", m.relRmse},
                        {"mean_rel_error", m.meanRelError},
                        {"mean_abs_error", m.meanAbsError},
                        {"max_abs_error", m.maxAbsError},
                        {"mean_ratio", m.meanRatio},
                        {"mean_a", m.meanA},
                        {"mean_b", m.meanB},
                        {"units", "luminance of radiance, W/(m^2 sr); relative errors against B's mean"}};
    if (m.noiseKnown) {
      j["reference_noise_rel_rmse"] = {m.noiseRelRmseLo, m.noiseRelRmseHi};
      j["rel_rmse_reference_noise_removed"] = {m.relRmseDenoisedLo, m.relRmseDenoisedHi};
    }
    if (a.mask) j["mask_object_id"] = *a.mask;
    if (!exclude.empty()) j["excluded_object_ids"] = exclude;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("A = %s, B = %s (reference)%s\n", a.a.c_str(), a.b.c_str(),
                a.mask ? (", object " + std::to_string(*a.mask) + " only").c_str() : "");
    std::printf("  pixels            %zu\n", m.pixels);
    std::printf("  rel RMSE          %.4g\n", m.relRmse);
    std::printf("  mean rel error    %.4g\n", m.meanRelError);
    std::printf("  mean abs error    %.4g W/(m^2 sr)\n", m.meanAbsError);
    std::printf("  max abs error     %.4g W/(m^2 sr)\n", m.maxAbsError);
    std::printf("  mean A / mean B   %.5f\n", m.meanRatio);
    if (m.noiseKnown) {
      // A range: B's variance is known per channel, and the channels' noise may or may not be correlated.
      std::printf("  B's own noise     %.4g - %.4g (rel RMSE of B against its expectation)\n", m.noiseRelRmseLo, m.noiseRelRmseHi);
      std::printf("  rel RMSE, B's noise taken out  %.4g - %.4g\n", m.relRmseDenoisedLo, m.relRmseDenoisedHi);
    }
    if (!a.out.empty()) std::printf("  difference        %s (red: A brighter, blue: A darker, +-25 %% of mean B)\n", a.out.c_str());
  }
  return 0;
}
