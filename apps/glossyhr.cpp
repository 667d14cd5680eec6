// glossyhr: the command line. `solve` runs the radiosity solver on a scene and writes stats.json,
// solution.vtp, solution.ghrs and one EXR + PNG per camera; `render` re-renders a saved solution;
// `lobe` measures one material's reflected lobe in a directional basis (apps/lobe_command.cpp);
// `reference` path-traces reference images and `compare` measures one image against another; `view`
// shows a saved solution in a window or replays a camera path (apps/view_command.cpp).
// Input is validated completely before the output folder is touched; every flag against the limits
// table the scene readers use (flag_checks.h); a command-line error exits 2 like any bad input.
#include <CLI/CLI.hpp>
#include <hr/camera.h>
#include <hr/echo.h>
#include <hr/output.h>
#include <hr/output_set.h>
#include <hr/solution_view.h>
#include <hr/solver.h>
#include <tbb/global_control.h>

#include <cstdio>
#include <filesystem>
#include <optional>
#include <thread>

#include "extension_cli.h"
#include "host_table.h"
#include "flag_checks.h"
#include "info_command.h"
#include "inspect_command.h"
#include "lobe_command.h"
#include "reference_command.h"
#include "study_command.h"
#include "ab_command.h"
#include "view_command.h"
#include "registry.h"

namespace fs = std::filesystem;

namespace {

struct SolveArgs {
  std::string scene, out = "out", algorithm = "diffuse", host = "bright";
  std::string iteration;  // empty: the host's own scheme (the first of its HostEntry::iterations)
  std::optional<double> eps, tolerance, shootFraction;
  std::optional<int> maxLevel, rays, threads, maxIterations;
  std::optional<long long> seed;
  std::optional<double> maxImbalance, memoryMb;
  bool quiet = false, lambertian = false, flat = false;
  ExtensionOptions extension;
};

void writeImages(const hr::Solution& sol, const hr::Extension* ext, hr::OutputSet& out, bool quiet) {
  for (const hr::Camera& cam : sol.cameras) {
    hr::Image img = hr::render(sol, cam, ext);
    hr::writeExr(img, out.path(cam.name + ".exr"));
    hr::writePng(img, out.path(cam.name + ".png"));
    if (!quiet) std::fprintf(stderr, "rendered camera \"%s\" (%dx%d)\n", cam.name.c_str(), cam.width, cam.height);
  }
}

int runSolve(const SolveArgs& a) {
  namespace L = hr::limits;
  checkFlag("--eps", a.eps, L::kEps);
  checkFlag("--max-level", a.maxLevel, L::kMaxLevel);
  checkFlag("--rays-per-link", a.rays, L::kRaysPerLink);
  checkFlag("--max-iterations", a.maxIterations, L::kMaxIterations);
  checkFlag("--tolerance", a.tolerance, L::kTolerance);
  checkFlag("--threads", a.threads, L::kThreads);
  checkFlag("--seed", a.seed, L::kSeed);
  const HostEntry& host = findHost(a.host);
  const std::string iteration = a.iteration.empty() ? host.defaultIteration() : a.iteration;
  if (!host.iterates(iteration))
    throw hr::InputError("--iteration " + iteration + ": the " + host.name + " host iterates by " + host.iterations +
                         " only");
  checkFlag("--max-imbalance", a.maxImbalance, L::kMaxImbalance);
  checkFlag("--memory-mb", a.memoryMb, L::kMemoryMb);
  if (a.memoryMb && iteration != "gather")
    throw hr::InputError("--memory-mb: steers the refinement of gathering only (--iteration gather" +
                         std::string(host.iterates("gather") ? "" : ", which the " + std::string(host.name) + " host has not") +
                         ")");
  checkFlag("--shoot-fraction", a.shootFraction, L::kShootFraction);
  if (a.shootFraction && iteration != "shoot") throw hr::InputError("--shoot-fraction: only with --iteration shoot");
  hr::Progress progress(a.quiet);
  progress.phase("loading scene");
  hr::Scene scene = a.scene.empty() ? hr::defaultScene() : hr::loadScene(a.scene);
  for (const auto& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  for (const auto& d : scene.dropped) std::fprintf(stderr, "note: dropped or approximated: %s\n", d.c_str());
  if (a.lambertian) {
    // rho_d + rho_s is the modified Phong albedo at normal incidence: the Lambertian stand-in
    // reflects as much light, so an A/B pair of runs holds the same energy.
    std::size_t n = 0;
    for (hr::Material& m : scene.materials)
      if (m.glossy()) m.diffuse += m.specular, m.specular = hr::Rgb(0.0), ++n;
    if (!a.quiet) std::fprintf(stderr, "note: --lambertian: %zu glossy material(s) made Lambertian (rho_d + rho_s)\n", n);
  }
  std::unique_ptr<hr::Extension> ext = a.extension.make(a.algorithm);
  hr::SolverOptions opt = hr::SolverOptions::from(scene.settings);
  if (a.eps) opt.eps = *a.eps;
  if (a.maxLevel) opt.maxLevel = *a.maxLevel;
  if (a.rays) opt.raysPerLink = *a.rays;
  if (a.maxIterations) opt.maxIterations = *a.maxIterations;
  if (a.tolerance) opt.tolerance = *a.tolerance;
  if (a.seed) opt.seed = static_cast<std::uint64_t>(*a.seed);
  if (a.maxImbalance) opt.maxImbalance = *a.maxImbalance;
  if (a.memoryMb) opt.memoryBudgetBytes = static_cast<std::size_t>(*a.memoryMb * 1048576.0);
  opt.iteration = iteration == "shoot" ? hr::Iteration::Shoot : hr::Iteration::Gather;
  if (a.shootFraction) opt.shootFraction = *a.shootFraction;
  if (ext && opt.iteration == hr::Iteration::Shoot && !ext->canShoot())
    throw hr::InputError(host.iterates("gather")
                             ? "--iteration shoot: --algorithm " + a.algorithm + " gathers only (use --iteration gather)"
                             : "--algorithm " + a.algorithm + " gathers only, and --host " + host.name + " shoots only (use --host " +
                                   hostTable().front().name + " --iteration gather, or --algorithm is)");
  int threads = a.threads ? *a.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));

  // The output folder is checked (and stale staging from a killed run settled) before solving,
  // once the host knows the cameras (an automatic one needs the scene's bounds).
  std::optional<hr::OutputSet> outSet;
  HostJob job{scene, opt, ext, a.algorithm, progress, a.quiet, [&] {
                std::vector<std::string> names = {"solution.ghrs", "solution.vtp"};
                for (const hr::Camera& c : scene.cameras) names.insert(names.end(), {c.name + ".exr", c.name + ".png"});
                names.push_back("stats.json");
                outSet.emplace(a.out, names);
              }};
  HostResult res = host.solve(job);
  hr::OutputSet& out = *outSet;
  const hr::SolveStats& st = res.st;
  hr::Solution& sol = res.sol;
  sol.algorithm = a.algorithm;
  if (a.flat) {
    // Either host: each element's own radiosity in every output and in solution.ghrs (as `render
    // --flat` draws it); an extension's share is drawn as the extension draws it.
    hr::setSection(sol, "display", "flat");
    hr::reconstruct(sol);
  }
  if (ext) sol.extension = {std::string(ext->name()), ext->formatVersion(), {}, [&ext](std::ostream& o) { ext->save(o); }};
  for (const auto& e : sol.elements)
    if (!hr::allFinite(e.radiosity)) throw std::runtime_error("non-finite radiosity in the solution");
  hr::RunInfo run;
  run.scene = a.scene.empty() ? "built-in:cornell_box" : a.scene;
  run.host = host.name;
  run.algorithm = a.algorithm;
  run.eps = opt.eps;
  run.maxLevel = opt.maxLevel;
  run.threads = threads;
  run.raysPerLink = opt.raysPerLink;
  run.seed = opt.seed;
  run.maxImbalance = opt.maxImbalance;
  if (ext)
    for (const auto& e : ext->stats()) {
      if (e.text.empty())
        run.extension.emplace_back(e.name, e.value);
      else
        run.extensionText.emplace_back(e.name, e.text);
    }
  hr::saveSolution(sol, out.path("solution.ghrs"));
  hr::writeVtp(sol, out.path("solution.vtp"), ext.get());
  writeImages(sol, ext.get(), out, a.quiet);
  hr::writeFileAtomically(out.path("stats.json"), hr::statsJson(run, st, hr::peakRssBytes()));
  out.commit();

  if (!a.quiet) {
    hr::Rgb bal = st.emittedW - st.absorbedW - st.escapedW;
    std::fprintf(stderr,
                 "\nsummary: %s in %.2f s, %d %s, %s\n"
                 "  %zu patches -> %zu elements (%zu leaves), %zu clusters, %zu links, %llu rays\n"
                 "  power (W, green channel): emitted %.4g, absorbed %.4g (%.3g by back faces), escaped %.4g, imbalance %.2f%%\n",
                 run.scene.c_str(), st.tTotal, st.iterations,
                 st.iteration == hr::Iteration::Shoot ? "shooting pass(es)" : "iteration(s)",
                 st.converged ? "converged" : st.diverged ? "DIVERGING" : "NOT converged",
                 st.initialPatches, st.elements, st.leaves, st.clusters, st.links,
                 static_cast<unsigned long long>(st.rays), st.emittedW.y, st.absorbedW.y, st.backAbsorbedW.y, st.escapedW.y,
                 100.0 * bal.y / std::max(st.emittedW.y, 1e-300));
    // The extension's choices (e.g. the basis of each glossy material under --basis auto).
    for (const auto& [name, text] : run.extensionText) std::fprintf(stderr, "  %s: %s = %s\n", a.algorithm.c_str(), name.c_str(), text.c_str());
    if (st.iteration == hr::Iteration::Shoot)
      std::fprintf(stderr, "  unshot power left: %.4g W (luminance; %.2e of emitted)\n", st.unshotW,
                   st.unshotW / std::max(hr::luminance(st.emittedW), 1e-300));
  }
  if (!st.energyOk) {
    hr::Rgb bal = st.emittedW - st.absorbedW - st.escapedW;
    std::fprintf(stderr,
                 "\n*** ENERGY CHECK FAILED: the answer is NOT trustworthy ***\n"
                 "  the independent audit finds %.2f %% of the emitted power (green) unaccounted for "
                 "(emitted - absorbed - escaped = %.4g W); allowed: %.4g W (--max-imbalance %g of the "
                 "emitted power plus 3 standard errors of the audit)\n",
                 100.0 * bal.y / std::max(st.emittedW.y, 1e-300), bal.y, st.allowedImbalanceW.y, opt.maxImbalance);
  }
  std::printf("outputs in %s:\n", fs::absolute(a.out).string().c_str());
  for (const auto& w : out.finalPaths()) std::printf("  %s\n", w.c_str());
  // Loud even with --quiet: a diverging solve's outputs are kept for inspection, not for use.
  if (st.diverged)
    std::fprintf(stderr, "error: the solve is DIVERGING (energy is being created): stopped after iteration %d, "
                         "residual %.3g x the emitted power; its outputs are not a solution\n",
                 st.iterations, st.history.back().residualW / std::max(hr::luminance(st.emittedW), 1e-300));
  // A budget the run could not keep is said loudly too (the outputs are an answer, but not the one
  // asked for): beyond 10 % over it, exit 3.
  const double peakMB = double(hr::peakRssBytes()) / 1048576.0;
  const double overBudget = st.memoryBudgetBytes ? peakMB * 1048576.0 / double(st.memoryBudgetBytes) : 0.0;
  if (overBudget > 1.1)
    std::fprintf(stderr, "error: MEMORY BUDGET NOT KEPT: peak resident memory %.1f MB is %.0f %% of --memory-mb %.1f%s\n",
                 peakMB, 100.0 * overBudget, double(st.memoryBudgetBytes) / 1048576.0,
                 st.memoryBudgetExceeded ? " (the coarsest pass alone needs more)" : "");
  else if (st.memoryBudgetBytes && !a.quiet)
    std::fprintf(stderr, "  memory budget: peak %.1f MB of %.1f MB; refined down to eps %.3g\n", peakMB, double(st.memoryBudgetBytes) / 1048576.0, st.epsReached);
  return st.converged && st.energyOk && overBudget <= 1.1 ? 0 : 3;
}

struct RenderArgs {
  std::string solution, camera, image;
  std::vector<double> eye, lookAt, up;  // a camera the scene did not have
  double fov = 45.0;
  int width = 0, height = 0;
  bool quiet = false;
  bool flat = false;  // each leaf's own radiosity, unsmoothed: separates solution error from display
};

/// The camera a render asks for: a named one of the solution's, or one made from --eye and
/// --look-at (with --up, --fov and the size), or the solution's first.
hr::Camera chooseCamera(const RenderArgs& a, const hr::Solution& sol) {
  if (!a.eye.empty() || !a.lookAt.empty()) {
    if (!a.camera.empty()) throw hr::InputError("--camera and --eye/--look-at are alternatives: give one");
    if (a.eye.size() != 3 || a.lookAt.size() != 3) throw hr::InputError("--eye and --look-at: give both, as X,Y,Z");
    hr::Camera c;
    c.name = "custom";
    c.eye = {a.eye[0], a.eye[1], a.eye[2]};
    c.lookAt = {a.lookAt[0], a.lookAt[1], a.lookAt[2]};
    if (!a.up.empty()) {
      if (a.up.size() != 3) throw hr::InputError("--up: give X,Y,Z");
      c.up = {a.up[0], a.up[1], a.up[2]};
    }
    if (!hr::allFinite(c.eye) || !hr::allFinite(c.lookAt) || !hr::allFinite(c.up))
      throw hr::InputError("--eye/--look-at/--up: finite numbers only");
    if (glm::length(c.lookAt - c.eye) <= 0.0) throw hr::InputError("--look-at: must differ from --eye");
    if (glm::length(glm::cross(c.lookAt - c.eye, c.up)) <= 0.0) throw hr::InputError("--up: must not be parallel to the view");
    if (!(a.fov > 0.0 && a.fov < 180.0)) throw hr::InputError("--fov: degrees in (0, 180)");
    c.fovYDeg = a.fov;
    c.width = a.width > 0 ? a.width : sol.cameras.empty() ? 320 : sol.cameras.front().width;
    c.height = a.height > 0 ? a.height : sol.cameras.empty() ? 240 : sol.cameras.front().height;
    return c;
  }
  if (a.width > 0 || a.height > 0) throw hr::InputError("--width/--height: only with --eye and --look-at");
  std::string names;
  for (const auto& c : sol.cameras) names += (names.empty() ? "" : ", ") + c.name;
  for (const auto& c : sol.cameras)
    if (a.camera.empty() || c.name == a.camera) return c;
  throw hr::InputError("--camera: no camera " + hr::echo(a.camera) + " in " + a.solution + " (cameras: " +
                       hr::clipMessage(names, 400) + ")");
}

int runRender(const RenderArgs& a) {
  fs::path target(a.image);
  std::string kind = target.extension().string();
  if (kind != ".exr" && kind != ".png") throw hr::InputError("-o: image must end in .exr or .png");
  hr::Solution sol = hr::loadSolution(a.solution);
  hr::Camera cam = chooseCamera(a, sol);
  hr::SolutionView view(sol);
  std::unique_ptr<hr::Extension> ext = loadExtension(sol, view, a.solution);
  hr::OutputSet out(target.parent_path().string(), {target.filename().string()});
  if (a.flat && ext) throw hr::InputError("--flat: draws the Lambertian radiosity alone; not for a solution with an extension");
  hr::Image img = a.flat ? hr::render(sol, cam, [&](std::uint32_t leaf, const hr::Vec3&, const hr::Vec3&) {
    return sol.elements[leaf].radiosity / hr::kPi;
  })
                         : hr::render(sol, cam, ext.get());
  if (kind == ".exr")
    hr::writeExr(img, out.path(target.filename().string()));
  else
    hr::writePng(img, out.path(target.filename().string()));
  out.commit();
  if (!a.quiet) std::fprintf(stderr, "rendered camera \"%s\" to %s\n", cam.name.c_str(), a.image.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"glossyhr: hierarchical radiosity with a glossy extension"};
  app.require_subcommand(1);
  SolveArgs sa;
  auto* solve = app.add_subcommand("solve", "solve a scene (JSON); without SCENE the built-in Cornell box");
  solve->add_option("scene", sa.scene, "scene file (.json)");
  solve->add_option("-o,--output", sa.out, "output folder")->capture_default_str();
  solve->add_option("--eps", sa.eps, "relative refinement threshold (link error / emitted power)");
  solve->add_option("--max-level", sa.maxLevel, "maximum quadtree depth below a root patch");
  solve->add_option("--rays-per-link", sa.rays, "shadow rays per link (at least 32 on links from emitters)");
  solve->add_option("--max-iterations", sa.maxIterations, "maximum gathering iterations");
  solve->add_option("--tolerance", sa.tolerance, "stop when the power change is below this fraction of emitted");
  solve->add_option("--threads", sa.threads, "worker threads (default: all cores)");
  solve->add_option("--seed", sa.seed, "random seed for shadow-ray sampling");
  solve->add_option("--max-imbalance", sa.maxImbalance,
                    "exit 3 when the energy audit finds more than this fraction of the emitted power unaccounted "
                    "for (plus its noise); default 0.02");
  solve->add_option("--memory-mb", sa.memoryMb,
                    "peak resident memory budget, MB (gathering): refinement starts at eps 1e-2 and comes down "
                    "toward --eps pass by pass as far as the budget allows; exit 3 if the peak exceeds it by 10 %");
  solve->add_option("--algorithm", sa.algorithm, "extension from the table (diffuse)")->capture_default_str();
  solve->add_flag("--lambertian", sa.lambertian,
                  "replace each glossy material by a Lambertian one of the same normal-incidence albedo (rho_d + rho_s)");
  std::string hostHelp = "radiosity host:";
  for (const HostEntry& h : hostTable())
    hostHelp += std::string(" ") + h.name + " (" + h.summary + "; --algorithm " + h.algorithms + "; --iteration " +
                h.iterations + ")";
  solve->add_option("--host", sa.host, hostHelp)->capture_default_str();
  solve->add_option("--iteration", sa.iteration,
                    "gather (Jacobi over all links) or shoot (passes from the patches with the most unshot power); "
                    "default: the host's first (bright: gather, vision: shoot)")
      ->check(CLI::IsMember({"gather", "shoot"}));
  solve->add_option("--shoot-fraction", sa.shootFraction,
                    "shooting: patches with at least this fraction of the largest unshot power shoot together (default 0.1; 1: one per pass)");
  solve->add_flag("--flat", sa.flat,
                  "show each element's own radiosity, unsmoothed (default: smooth per vertex on both hosts)");
  solve->add_flag("--quiet", sa.quiet, "no progress on stderr");
  sa.extension.addTo(solve);
  RenderArgs ra0;
  auto* render = app.add_subcommand("render", "render a saved solution (.ghrs) again, from any camera");
  render->add_option("solution", ra0.solution, "solution.ghrs")->required();
  render->add_option("--camera", ra0.camera, "camera name (default: the first)");
  render->add_option("--eye", ra0.eye, "a new camera's eye X,Y,Z (m)")->delimiter(',')->expected(3);
  render->add_option("--look-at", ra0.lookAt, "a new camera's target X,Y,Z (m)")->delimiter(',')->expected(3);
  render->add_option("--up", ra0.up, "a new camera's up direction X,Y,Z")->delimiter(',')->expected(3);
  render->add_option("--fov", ra0.fov, "a new camera's vertical field of view, degrees")->capture_default_str();
  render->add_option("--width", ra0.width, "a new camera's width, pixels")->check(CLI::Range(1, 16384));
  render->add_option("--height", ra0.height, "a new camera's height, pixels")->check(CLI::Range(1, 16384));
  render->add_option("-o,--output", ra0.image, "output image (.exr or .png)")->required();
  render->add_flag("--flat", ra0.flat, "each leaf's own radiosity, unsmoothed (a diagnostic: solution vs display error)");
  render->add_flag("--quiet", ra0.quiet, "no progress on stderr");
  InspectArgs ia;
  auto* inspect = app.add_subcommand("inspect", "one element of a saved solution: its light and directional lobe");
  inspect->add_option("solution", ia.solution, "solution.ghrs")->required();
  inspect->add_option("--element", ia.element, "element id (as in solution.vtp's element_id)");
  inspect->add_option("--point", ia.point, "the element under point X,Y,Z (m)")->delimiter(',')->expected(3);
  inspect->add_option("-o,--output", ia.out, "write the lobe as a VTK surface (.vtp)");
  inspect->add_flag("--json", ia.json, "print the report as JSON");
  LobeArgs la;
  auto* lobe = app.add_subcommand("lobe", "project one material's reflected lobe into a directional basis and measure it");
  lobe->add_option("--exponent", la.exponent, "Phong exponent n")->capture_default_str();
  lobe->add_option("--specular", la.specular, "specular reflectance rho_s")->capture_default_str();
  lobe->add_option("--diffuse", la.diffuse, "diffuse reflectance rho_d")->capture_default_str();
  lobe->add_option("--incident-deg", la.incidentDeg, "incident angle from the normal, degrees")->capture_default_str();
  lobe->add_option("--azimuth-deg", la.azimuthDeg, "incident azimuth, degrees")->capture_default_str();
  lobe->add_option("--basis", la.basis, "haar, tetra or sh")->capture_default_str();
  lobe->add_option("--eps", la.eps, "haar: refinement threshold (relative: fraction of the centre value; absolute: W/sr)");
  lobe->add_option("--min-level", la.minLevel, "haar: minimum level (default 2)");
  lobe->add_option("--max-level", la.maxLevel, "haar: maximum level (default 8)");
  lobe->add_option("--refiner", la.refiner, "haar: relative or absolute")->capture_default_str();
  lobe->add_option("--floor", la.floor, "haar, relative refiner: ignore variation below this fraction of the peak (default 1e-3)");
  lobe->add_flag("--no-hints", la.noHints, "haar: do not refine around the mirror direction");
  lobe->add_option("--level", la.level, "tetra: subdivision level (default 3)");
  lobe->add_option("--order", la.order, "sh: number of bands L, L^2 coefficients (default 8)");
  lobe->add_option("--quadrature", la.quadrature, "sh: Gauss-Legendre nodes in cos(theta) for the projection");
  lobe->add_flag("--json", la.json, "print the report as JSON");
  lobe->add_option("-o,--output", la.out, "write the lobe as a VTK surface (.vtp)");
  ReferenceArgs ra;
  auto* reference = app.add_subcommand("reference", "path-traced reference images of a scene (NEE + MIS)");
  reference->add_option("scene", ra.scene, "scene file (.json); without it the built-in Cornell box");
  reference->add_option("-o,--output", ra.out, "output folder")->capture_default_str();
  reference->add_option("--spp", ra.spp, "samples per pixel (default 64)");
  reference->add_option("--time-s", ra.timeS, "instead of --spp: add passes until this many seconds are spent");
  reference->add_option("--max-depth", ra.maxDepth, "maximum path length in bounces")->capture_default_str();
  reference->add_option("--threads", ra.threads, "worker threads (default: all cores)");
  reference->add_option("--seed", ra.seed, "random seed")->capture_default_str();
  reference->add_flag("--quiet", ra.quiet, "no progress on stderr");
  CompareArgs ca;
  auto* compare = app.add_subcommand("compare", "compare image A with reference B (EXR): errors and a difference image");
  compare->add_option("a", ca.a, "candidate image (.exr)")->required();
  compare->add_option("b", ca.b, "reference image (.exr)")->required();
  compare->add_option("--mask", ca.mask, "compare only pixels showing this object id (file order)");
  compare->add_option("--exclude", ca.exclude, "leave out pixels showing these object ids and their bordering pixels, e.g. the lights (ID,ID,...)")
      ->delimiter(',');
  compare->add_option("--exclude-lights", ca.lightsOf,
                      "leave out the emitting objects of this scene (JSON or MGF; the one the images show), as --exclude does");
  compare->add_option("--reference-variance", ca.variance,
                      "B's variance image (REF.var.exr, as `reference` writes it): also report B's own noise and the "
                      "rel. RMSE with it taken out");
  compare->add_option("-o,--output", ca.out, "false-colour difference image (.png)");
  compare->add_flag("--json", ca.json, "print the metrics as JSON");
  ViewArgs va;
  auto* viewCmd = app.add_subcommand("view", "a saved solution in an interactive window, or a camera path replayed headless");
  addViewOptions(viewCmd, va);
  StudyArgs sta;
  auto* studyCmd = app.add_subcommand("study", "what accuracy costs: a grid of solves against a reference and the path tracer");
  studyCmd->add_option("scene", sta.scene, "scene file (.json or .mgf)")->required();
  studyCmd->add_option("-o,--output", sta.out, "output folder (study.csv, study.json, plots)")->capture_default_str();
  studyCmd->add_option("--grid", sta.grid, std::string("configurations, KEY=V,V;KEY=V,...; products joined by '|' run in turn (default \"") + kDefaultStudyGrid + "\")");
  studyCmd->add_option("--reference-spp", sta.referenceSpp, "samples per pixel of the cached reference (default 1024)");
  studyCmd->add_option("--reference", sta.reference, "instead: this EXR is the reference (one-camera scenes)");
  studyCmd->add_option("--views", sta.views, "walkthrough length for the economics columns (default 10)");
  studyCmd->add_option("--cache", sta.cache, "where references are cached (default ~/.cache/glossyhr)");
  studyCmd->add_option("--threads", sta.threads, "worker threads of each run (default: all cores)");
  studyCmd->add_flag("--no-plots", sta.noPlots, "write the CSV and JSON only");
  studyCmd->add_flag("--quiet", sta.quiet, "no progress on stderr");
  AbArgs aba;
  auto* abCmd = app.add_subcommand("ab", "a scene solved diffuse-only (glossy made Lambertian) and glossy, side by side");
  abCmd->add_option("scene", aba.scene, "scene file (.json or .mgf) with glossy materials")->required();
  abCmd->add_option("-o,--output", aba.out, "output folder")->capture_default_str();
  abCmd->add_option("--algorithm", aba.algorithm, "the glossy run's extension")->capture_default_str();
  abCmd->add_option("--eps", aba.eps, "relative refinement threshold of both runs");
  abCmd->add_option("--threads", aba.threads, "worker threads of each run (default: all cores)");
  abCmd->add_flag("--quiet", aba.quiet, "no progress on stderr");
  std::string infoScene;
  bool infoJson = false;
  auto* info = app.add_subcommand("info", "what a scene (JSON or MGF) holds");
  info->add_option("scene", infoScene, "scene file (.json or .mgf)")->required();
  info->add_flag("--json", infoJson, "print the report as JSON");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 exits 104-114 for its errors; a bad command line is bad input like any other: 2.
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (*solve) return runSolve(sa);
    if (*render) return runRender(ra0);
    if (*inspect) return runInspect(ia);
    if (*lobe) return runLobe(la);
    if (*reference) return runReference(ra);
    if (*compare) return runCompare(ca);
    if (*info) return runInfo(infoScene, infoJson);
    if (*viewCmd) return runView(va);
    if (*studyCmd) return runStudy(sta);
    if (*abCmd) return runAb(aba);
  } catch (const hr::InputError& e) {
    std::fprintf(stderr, "error: %s\n", hr::clipMessage(e.what()).c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", hr::clipMessage(e.what()).c_str());
    return 1;
  }
  return 0;
}
