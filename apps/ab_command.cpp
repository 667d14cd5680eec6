// `glossyhr ab`: one scene solved twice, diffuse-only (`solve --lambertian`: each glossy material
// replaced by a Lambertian one of the same normal-incidence albedo, so both runs hold the same energy)
// and glossy; each in its own process, so time and peak memory are each run's own. Images side by
// side with one exposure, a difference image, both runs' stats and a summary of what the glossy run
// costs and what it changes, object by object. All files appear together or not at all.
#include "ab_command.h"

#include <hr/echo.h>
#include <hr/output.h>
#include <hr/output_set.h>
#include <hr/scene.h>
#include <ref/compare.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>


#include "flag_checks.h"
#include "study/child.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json readJson(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

/// Mean luminance (W/(m^2 sr)) and pixel count per object seen in an image, by pixel centre.
std::map<std::uint32_t, std::pair<double, std::size_t>> objectMeans(const hr::Image& img) {
  std::map<std::uint32_t, std::pair<double, std::size_t>> m;
  for (std::size_t i = 0; i < img.objectId.size(); ++i) {
    auto& [sum, n] = m[img.objectId[i]];
    sum += hr::luminance(hr::Rgb(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]));
    ++n;
  }
  for (auto& [id, v] : m) v.first /= double(v.second);
  return m;
}

double imbalancePct(const json& st) {
  const auto& e = st.at("energy");
  double emitted = e.at("emitted_w")[1].get<double>();
  return emitted > 0 ? 100.0 * e.at("imbalance_w")[1].get<double>() / emitted : 0.0;
}

}  // namespace

int runAb(const AbArgs& a) {
  checkFlag("--eps", a.eps, hr::limits::kEps);
  checkFlag("--threads", a.threads, hr::limits::kThreads);
  hr::Scene scene = hr::loadScene(a.scene);
  std::size_t glossy = 0;
  for (const hr::Material& m : scene.materials) glossy += m.glossy();
  if (glossy == 0)
    throw hr::InputError(a.scene + ": no glossy material (specular > 0): the A/B pair would be one run twice");
  const std::vector<std::uint32_t> lights = hr::emitterObjects(scene);
  const study::ScratchDir scratchDir("ab");
  const fs::path& scratch = scratchDir.path();

  struct Run {
    const char* name;
    std::vector<std::string> flags;
    json stats;
  };
  std::vector<Run> runs = {{"diffuse", {"--lambertian"}, {}}, {"glossy", {"--algorithm", a.algorithm}, {}}};
  for (Run& r : runs) {
    std::vector<std::string> args = {"solve", a.scene, "-o", (scratch / r.name).string(), "--quiet"};
    args.insert(args.end(), r.flags.begin(), r.flags.end());
    if (a.eps) args.insert(args.end(), {"--eps", std::to_string(*a.eps)});
    if (a.threads) args.insert(args.end(), {"--threads", std::to_string(*a.threads)});
    if (!a.quiet) std::fprintf(stderr, "ab: solving %s (%s) ...\n", r.name, r.flags.back().c_str());
    std::string log = (scratch / (std::string(r.name) + ".log")).string();
    study::ChildResult c = study::runSelf(args, log);
    if (c.exitCode == 2) throw hr::InputError("the " + std::string(r.name) + " run refused its input: " + study::failureReason(log));
    if (c.exitCode != 0 && c.exitCode != 3)
      throw std::runtime_error("the " + std::string(r.name) + " run failed (exit " + std::to_string(c.exitCode) +
                               "): " + study::failureReason(log));
    r.stats = readJson(scratch / r.name / "stats.json");
    r.stats["exit_code"] = c.exitCode;
  }

  std::vector<std::string> cameras;
  for (const auto& entry : fs::directory_iterator(scratch / "glossy"))
    if (entry.path().extension() == ".exr") cameras.push_back(entry.path().stem().string());
  std::sort(cameras.begin(), cameras.end());
  std::vector<std::string> names = {"ab.json", "diffuse_stats.json", "glossy_stats.json"};
  for (const auto& c : cameras)
    names.insert(names.end(), {c + "_diffuse.exr", c + "_glossy.exr", c + "_side_by_side.png", c + "_difference.png"});
  hr::OutputSet out(a.out, names);

  json doc = {{"scene", a.scene},
              {"glossy_materials_made_lambertian", glossy},
              {"units", "time s; memory MiB; luminance W/(m^2 sr); power W (green channel)"}};
  for (const Run& r : runs) {
    doc[r.name] = {{"time_s", r.stats.at("time_s").at("total")},
                   {"peak_rss_mib", r.stats.at("memory_bytes").at("peak_rss").get<double>() / (1024.0 * 1024.0)},
                   {"elements", r.stats.at("counts").at("elements")},
                   {"links", r.stats.at("counts").at("links")},
                   {"emitted_w", r.stats.at("energy").at("emitted_w")[1]},
                   {"absorbed_w", r.stats.at("energy").at("absorbed_w")[1]},
                   {"escaped_w", r.stats.at("energy").at("escaped_w")[1]},
                   {"imbalance_pct", imbalancePct(r.stats)},
                   {"exit_code", r.stats.at("exit_code")}};
    hr::writeFileAtomically(out.path(std::string(r.name) + "_stats.json"), r.stats.dump(2) + "\n");
  }
  for (const std::string& cam : cameras) {
    hr::Image d = hr::readExr((scratch / "diffuse" / (cam + ".exr")).string());
    hr::Image g = hr::readExr((scratch / "glossy" / (cam + ".exr")).string());
    hr::writeExr(d, out.path(cam + "_diffuse.exr"));
    hr::writeExr(g, out.path(cam + "_glossy.exr"));
    // Side by side with the glossy image's exposure for both: a difference in brightness is light.
    hr::Image both;
    const int gap = 4;
    both.width = 2 * g.width + gap, both.height = g.height;
    both.rgb.assign(std::size_t(3) * both.width * both.height, 0.0f);
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x)
        for (int c = 0; c < 3; ++c) {
          std::size_t src = 3 * (std::size_t(y) * g.width + x) + c;
          both.rgb[3 * (std::size_t(y) * both.width + x) + c] = d.rgb[src];
          both.rgb[3 * (std::size_t(y) * both.width + x + g.width + gap) + c] = g.rgb[src];
        }
    hr::writePng(both, out.path(cam + "_side_by_side.png"), hr::pngExposure(g));
    ref::writeDifferencePng(g, d, out.path(cam + "_difference.png"), -1, 0.25, lights);
    ref::Metrics m = ref::compare(g, d, -1, "glossy", "diffuse", lights);
    // What the glossy run changes, object by object: largest change of mean luminance first.
    auto md = objectMeans(d), mg = objectMeans(g);
    json objects = json::array();
    for (const auto& [id, v] : mg) {
      if (id >= scene.objects.size() || !md.count(id) || std::find(lights.begin(), lights.end(), id) != lights.end())
        continue;
      double before = md[id].first, after = v.first;
      objects.push_back({{"object", id},
                         {"where", scene.objects[id].where},
                         {"material", scene.objects[id].material},
                         {"pixels", v.second},
                         {"diffuse_mean", before},
                         {"glossy_mean", after},
                         {"change_pct", before > 0 ? 100.0 * (after - before) / before : 0.0}});
    }
    std::sort(objects.begin(), objects.end(), [](const json& x, const json& y) {
      return std::abs(x["glossy_mean"].get<double>() - x["diffuse_mean"].get<double>()) *
                 x["pixels"].get<double>() >
             std::abs(y["glossy_mean"].get<double>() - y["diffuse_mean"].get<double>()) * y["pixels"].get<double>();
    });
    doc["cameras"][cam] = {{"rel_difference_rmse", m.relRmse}, {"mean_ratio_glossy_over_diffuse", m.meanRatio},
                           {"objects_by_change", objects}};
  }
  hr::writeFileAtomically(out.path("ab.json"), doc.dump(2) + "\n");
  out.commit();

  if (!a.quiet) {
    const json &D = doc["diffuse"], &G = doc["glossy"];
    std::fprintf(stderr,
                 "\nsummary: %s, diffuse-only (%zu glossy material(s) made Lambertian) vs glossy (--algorithm %s)\n"
                 "  time %.2f s vs %.2f s (x%.2f), peak memory %.0f vs %.0f MiB (x%.2f)\n"
                 "  elements %zu vs %zu, links %zu vs %zu, energy imbalance %.2f %% vs %.2f %%\n",
                 a.scene.c_str(), glossy, a.algorithm.c_str(), D["time_s"].get<double>(), G["time_s"].get<double>(),
                 G["time_s"].get<double>() / std::max(1e-9, D["time_s"].get<double>()), D["peak_rss_mib"].get<double>(),
                 G["peak_rss_mib"].get<double>(), G["peak_rss_mib"].get<double>() / std::max(1e-9, D["peak_rss_mib"].get<double>()),
                 D["elements"].get<std::size_t>(), G["elements"].get<std::size_t>(), D["links"].get<std::size_t>(),
                 G["links"].get<std::size_t>(), D["imbalance_pct"].get<double>(), G["imbalance_pct"].get<double>());
    for (const auto& [cam, c] : doc["cameras"].items()) {
      std::fprintf(stderr, "  camera %s: image mean glossy / diffuse %.3f, relative RMS difference %.3f; largest changes:\n",
                   cam.c_str(), c["mean_ratio_glossy_over_diffuse"].get<double>(), c["rel_difference_rmse"].get<double>());
      int shown = 0;
      for (const auto& o : c["objects_by_change"]) {
        if (shown++ == 5) break;
        std::fprintf(stderr, "    %-40s (%s): %+.1f %%\n", hr::clipMessage(o["where"].get<std::string>(), 40).c_str(),
                     o["material"].get<std::string>().c_str(), o["change_pct"].get<double>());
      }
    }
  }
  std::printf("outputs in %s:\n", fs::absolute(a.out).string().c_str());
  for (const auto& w : out.finalPaths()) std::printf("  %s\n", w.c_str());
  return 0;
}
