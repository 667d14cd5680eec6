// `glossyhr study`: grid specs expand to the configurations they name (and refuse what they cannot);
// the walkthrough economics against closed forms; and a tiny study end to end through the real
// command line: its CSV's columns, errors falling as the threshold falls, a broken configuration
// reported as a row and not fatal to the sweep.
#include <gtest/gtest.h>
#include <hr/types.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "helpers.h"
#include "study/economics.h"
#include "study/grid.h"
#include "test_dir.h"

namespace fs = std::filesystem;

namespace {

study::GridKeys keys() {
  study::GridKeys k;
  k.core = {"eps", "max-level"};
  k.byAlgorithm = {{"diffuse", {}}, {"is", {"basis", "dir-eps"}}};
  return k;
}

std::vector<std::string> labels(const std::vector<study::Config>& cs) {
  std::vector<std::string> out;
  for (const auto& c : cs) out.push_back(study::label(c));
  return out;
}

std::string thrownBy(const std::string& spec) {
  try {
    study::parseGrid(spec, keys());
  } catch (const hr::InputError& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

}  // namespace

TEST(StudyGrid, CartesianProductWithoutKeysAnAlgorithmDoesNotTake) {
  auto cs = study::parseGrid("eps=1e-3,1e-4; algorithm=diffuse,is; basis=haar,sh", keys());
  // The diffuse core takes no basis: two configurations, not four that differ only in an unused flag.
  std::vector<std::string> want = {"algorithm=diffuse eps=1e-3",          "algorithm=diffuse eps=1e-4",
                                   "algorithm=is eps=1e-3 basis=haar",    "algorithm=is eps=1e-3 basis=sh",
                                   "algorithm=is eps=1e-4 basis=haar",    "algorithm=is eps=1e-4 basis=sh"};
  EXPECT_EQ(labels(cs), want);
  EXPECT_EQ(study::value(cs[3], "basis"), "sh");
  EXPECT_EQ(study::value(cs[0], "basis"), "");
  // Without an algorithm key the grid is the diffuse core's.
  EXPECT_EQ(labels(study::parseGrid("max-level=3", keys())), std::vector<std::string>{"algorithm=diffuse max-level=3"});
}

TEST(StudyGrid, ProductsJoinedByABarAreSweptInTurnEachConfigurationOnce) {
  auto cs = study::parseGrid("algorithm=is;basis=haar;dir-eps=0.5,0.1 | algorithm=is;basis=sh,haar;dir-eps=0.5", keys());
  // The second product's haar at 0.5 is the first's: solved once.
  std::vector<std::string> want = {"algorithm=is basis=haar dir-eps=0.5", "algorithm=is basis=haar dir-eps=0.1",
                                   "algorithm=is basis=sh dir-eps=0.5"};
  EXPECT_EQ(labels(cs), want);
  EXPECT_NE(thrownBy("eps=1 | ").find("an empty product"), std::string::npos) << thrownBy("eps=1 | ");
  EXPECT_NE(thrownBy("eps=1 | colour=red").find("unknown key \"colour\""), std::string::npos);
}

TEST(StudyGrid, RefusesWhatItCannotSweepNamingTheCulprit) {
  EXPECT_NE(thrownBy("colour=red").find("unknown key \"colour\" (keys: algorithm, eps, max-level, basis, dir-eps)"),
            std::string::npos)
      << thrownBy("colour=red");
  EXPECT_NE(thrownBy("algorithm=rt").find("algorithm \"rt\" is not in the table (diffuse, is)"), std::string::npos);
  EXPECT_NE(thrownBy("eps=1,1").find("eps: value \"1\" repeated"), std::string::npos);
  EXPECT_NE(thrownBy("eps=1,").find("eps: an empty value"), std::string::npos);
  EXPECT_NE(thrownBy("eps").find("\"eps\" is not KEY=VALUE"), std::string::npos);
  EXPECT_NE(thrownBy("eps=1;eps=2").find("key \"eps\" given twice"), std::string::npos);
}

TEST(StudyEconomics, PowerLawFitAndBreakEvenMatchClosedForms) {
  // A tracer whose error is 2 t^-1/2 exactly: the fit recovers it, and reads 0.1 at t = 400 s.
  std::vector<study::CurvePoint> pts;
  for (double t : {1.0, 4.0, 16.0, 64.0}) pts.push_back({t, 2.0 / std::sqrt(t)});
  auto fit = study::fitPowerLaw(pts);
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->b, -0.5, 1e-12);
  EXPECT_NEAR(fit->secondsFor(0.1), 400.0, 1e-9);
  // Solve 10 s, render 0.1 s, tracer 1.1 s per image at that error: saves 1 s a view, pays off at 10.
  pts = {{1.0, 1.1}, {4.0, 0.55}};  // error = 1.1 t^-1/2: 1.1 s reaches error 1.1 / sqrt(1.1)
  fit = study::fitPowerLaw(pts);
  ASSERT_TRUE(fit);
  auto e = study::economics(*fit, 1.1 / std::sqrt(1.1), 10.0, 0.1, 10);
  EXPECT_NEAR(e.tracerSecondsPerImage, 1.1, 1e-9);
  ASSERT_TRUE(e.breakEvenViews);
  EXPECT_EQ(*e.breakEvenViews, 10.0);
  EXPECT_NEAR(e.ratioAtViews, 11.0 / 11.0, 1e-9);
  // A render slower than the tracer never pays off.
  EXPECT_FALSE(study::economics(*fit, 1.1 / std::sqrt(1.1), 10.0, 2.0, 10).breakEvenViews);
  // Errors that do not fall with time, or a single time, cannot be fitted.
  EXPECT_FALSE(study::fitPowerLaw({{1.0, 0.1}, {2.0, 0.2}}));
  EXPECT_FALSE(study::fitPowerLaw({{1.0, 0.1}, {1.0, 0.2}}));
}

TEST(StudyCli, TinyGridEndToEnd) {
  // The Cornell box at 48 x 48 pixels, so the reference and the sweep take seconds.
  std::ifstream in(std::string(GHR_SOURCE_DIR) + "/scenes/cornell_box.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  for (auto& c : scene["cameras"]) c["width"] = 48, c["height"] = 48;
  fs::path dir = testutil::testDir();
  std::ofstream(dir / "box.json") << scene.dump();
  std::string out;
  int rc = testutil::runCli("study " + (dir / "box.json").string() +
                                " --grid 'eps=1e-1,1e-2,1e-3;rays-per-link=4,0' --reference-spp 256 --cache " +
                                (dir / "cache").string() + " -o " + (dir / "study").string(),
                            out);
  ASSERT_EQ(rc, 0) << out;
  std::ifstream csv(dir / "study" / "study.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header,
            "kind,label,algorithm,eps,rays-per-link,spp,status,exit_code,camera,seconds,peak_rss_mb,coefficients,elements,"
            "links,imbalance_pct,rel_rmse,mean_ratio,render_s,tracer_s_at_equal_error,break_even_views,ratio_at_10_views");
  std::vector<double> errors;
  int failed = 0, tracer = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::string cell;
    std::istringstream ls(line);
    bool quoted = false;
    char ch;
    while (ls.get(ch)) {  // a quoted failure reason may hold commas
      if (ch == '"') quoted = !quoted;
      else if (ch == ',' && !quoted) f.push_back(cell), cell.clear();
      else cell += ch;
    }
    f.push_back(cell);
    ASSERT_EQ(f.size(), 21u) << line;
    if (f[0] == "path_tracer") ++tracer;
    else if (f[4] == "0") {
      ++failed;
      EXPECT_EQ(f[6].rfind("failed: error: --rays-per-link", 0), 0u) << line;
      EXPECT_EQ(f[7], "2");
      EXPECT_EQ(f[15], "") << "no error for a failed run";
    } else {
      EXPECT_EQ(f[6], "ok") << line;
      errors.push_back(std::stod(f[15]));
      EXPECT_GT(std::stod(f[9]), 0.0);
      EXPECT_GT(std::stod(f[10]), 0.0);
    }
  }
  EXPECT_EQ(failed, 3);
  EXPECT_EQ(tracer, 3) << "4, 16 and 64 spp (a quarter of the reference's 256 at most)";
  ASSERT_EQ(errors.size(), 3u);
  // eps 1e-1, 1e-2, 1e-3 in that order: each finer threshold is closer to the reference.
  EXPECT_GT(errors[0], errors[1]);
  EXPECT_GT(errors[1], errors[2]);
  EXPECT_LT(errors[2], 0.2);
  EXPECT_TRUE(fs::exists(dir / "study" / "study.json"));
  EXPECT_GT(fs::file_size(dir / "study" / "error_vs_time.png"), 1000u);
  EXPECT_GT(fs::file_size(dir / "study" / "error_vs_memory.png"), 1000u);
  // A second study of the same scene reads the reference from the cache.
  rc = testutil::runCli("study " + (dir / "box.json").string() + " --grid eps=1e-1 --reference-spp 256 --no-plots --cache " +
                            (dir / "cache").string() + " -o " + (dir / "again").string(),
                        out);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("from the cache"), std::string::npos) << out;
}

TEST(StudyCli, BadGridExitsTwoAndWritesNothing) {
  fs::path dir = testutil::testDir();
  std::string out;
  int rc = testutil::runCli("study " + std::string(GHR_SOURCE_DIR) + "/scenes/cornell_box.json --grid colour=red -o " +
                                (dir / "study").string(),
                            out);
  EXPECT_EQ(WEXITSTATUS(rc), 2) << out;
  EXPECT_NE(out.find("unknown key \"colour\""), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "study"));
}
