// The reference and compare commands. Input is validated before the output folder is touched; every
// file goes through the core's atomic writers.
#include "reference_command.h"

#include <hr/camera.h>
#include <ref/compare.h>
#include <ref/path_tracer.h>
#include <tbb/global_control.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

namespace fs = std::filesystem;

int runReference(const ReferenceArgs& a) {
  if (a.spp > 0 && a.timeS > 0) throw hr::InputError("--spp and --time-s are alternatives: give one");
  if (a.spp == 0 || a.spp < -1) throw hr::InputError("--spp must be at least 1");
  if (a.timeS == 0.0 || (a.timeS < 0 && a.timeS != -1.0)) throw hr::InputError("--time-s must be positive");
  if (a.maxDepth < 1) throw hr::InputError("--max-depth must be at least 1");
  hr::Progress progress(a.quiet);
  progress.phase("loading scene");
  hr::Scene scene = a.scene.empty() ? hr::defaultScene() : hr::loadScene(a.scene);
  for (const auto& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  for (const auto& d : scene.dropped) std::fprintf(stderr, "note: dropped or approximated: %s\n", d.c_str());
  int threads = a.threads > 0 ? a.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  hr::TessellationReport rep;
  std::vector<hr::Patch> patches = hr::buildPatches(scene, rep);
  if (rep.droppedZeroArea) std::fprintf(stderr, "warning: dropped %zu zero-area face(s)\n", rep.droppedZeroArea);
  hr::Aabb box;
  for (const auto& p : patches)
    for (int k = 0; k < p.poly.n; ++k) box.grow(p.poly.v[k]);
  if (scene.cameras.empty()) scene.cameras.push_back(hr::autoCamera(box));
  ref::PathTracer pt(scene, std::move(patches));
  ref::Options o;
  o.spp = a.spp > 0 ? a.spp : 64;
  o.timeS = a.timeS > 0 ? a.timeS : 0.0;
  o.maxDepth = a.maxDepth;
  o.seed = static_cast<std::uint64_t>(a.seed);

  std::vector<std::pair<hr::Camera, ref::CameraResult>> results;
  for (const hr::Camera& cam : scene.cameras) {
    progress.phase("path tracing camera \"" + cam.name + "\"");
    results.emplace_back(cam, pt.render(cam, o, &progress));
  }
  progress.phase("writing outputs");
  fs::create_directories(a.out);
  std::vector<std::string> written;
  nlohmann::json stats;
  stats["scene"] = a.scene.empty() ? "built-in:cornell_box" : a.scene;
  stats["algorithm"] = "path tracing, next-event estimation + BRDF sampling (MIS, power heuristic), Russian roulette";
  stats["max_depth"] = a.maxDepth;
  stats["seed"] = a.seed;
  stats["threads"] = threads;
  stats["units"] = "radiance W/(m^2 sr); variance of the pixel mean (W/(m^2 sr))^2";
  nlohmann::json cams = nlohmann::json::array();
  for (auto& [cam, r] : results) {
    std::string base = (fs::path(a.out) / cam.name).string();
    hr::writeExr(r.image, base + ".exr");
    hr::writePng(r.image, base + ".png");
    hr::Image var = r.image;
    var.rgb = r.variance;
    hr::writeExr(var, base + ".var.exr");
    written.insert(written.end(), {base + ".exr", base + ".png", base + ".var.exr"});
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
  std::string sj = (fs::path(a.out) / "stats.json").string();
  hr::writeFileAtomically(sj, stats.dump(2) + "\n");
  written.push_back(sj);
  std::printf("outputs in %s:\n", fs::absolute(a.out).string().c_str());
  for (const auto& w : written) std::printf("  %s\n", w.c_str());
  return 0;
}

int runCompare(const CompareArgs& a) {
  if (!a.out.empty() && fs::path(a.out).extension() != ".png") throw hr::InputError("-o: the difference image must end in .png");
  hr::Image A = hr::readExr(a.a), B = hr::readExr(a.b);
  ref::Metrics m = ref::compare(A, B, a.mask, a.a, a.b);
  if (!a.out.empty()) ref::writeDifferencePng(A, B, a.out, a.mask);
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
    if (a.mask >= 0) j["mask_object_id"] = a.mask;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("A = %s, B = %s (reference)%s\n", a.a.c_str(), a.b.c_str(),
                a.mask >= 0 ? (", object " + std::to_string(a.mask) + " only").c_str() : "");
    std::printf("  pixels            %zu\n", m.pixels);
    std::printf("  rel RMSE          %.4g\n", m.relRmse);
    std::printf("  mean rel error    %.4g\n", m.meanRelError);
    std::printf("  mean abs error    %.4g W/(m^2 sr)\n", m.meanAbsError);
    std::printf("  max abs error     %.4g W/(m^2 sr)\n", m.maxAbsError);
    std::printf("  mean A / mean B   %.5f\n", m.meanRatio);
    if (!a.out.empty()) std::printf("  difference        %s (red: A brighter, blue: A darker, +-25 %% of mean B)\n", a.out.c_str());
  }
  return 0;
}
