// `glossyhr lobe` through the real command line: bad options (table-driven) exit non-zero with a
// message naming the option and write nothing; a good run reports every key and writes a lobe surface
// that VTK's own reader opens, with finite values.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <cmath>
#include <filesystem>

#include "helpers.h"
#include "test_dir.h"

namespace fs = std::filesystem;

namespace {

struct BadLobe {
  const char* name;
  const char* args;
  const char* expect;
};

void PrintTo(const BadLobe& c, std::ostream* os) { *os << c.name; }

class LobeErrors : public ::testing::TestWithParam<BadLobe> {};

TEST_P(LobeErrors, ClearMessageNonZeroExitNoOutput) {
  const BadLobe& c = GetParam();
  fs::path out = testutil::testDir() / "lobe.vtp";
  fs::remove(out);
  std::string text;
  int status = testutil::runCli(std::string("lobe ") + c.args + " -o " + out.string(), text);
  EXPECT_NE(status, 0) << text;
  EXPECT_NE(text.find(c.expect), std::string::npos) << "message names the option: " << text;
  EXPECT_FALSE(fs::exists(out)) << "no output may be written";
}

INSTANTIATE_TEST_SUITE_P(Table, LobeErrors,
                         ::testing::Values(BadLobe{"energy_gaining", "--specular 0.7 --diffuse 0.5", "must not exceed 1"},
                                           BadLobe{"negative_reflectance", "--specular -0.1", "no negative reflectance"},
                                           BadLobe{"grazing_incidence", "--incident-deg 95", "--incident-deg"},
                                           BadLobe{"negative_exponent", "--exponent -2", "--exponent"},
                                           BadLobe{"unknown_basis", "--basis wavelet", "valid: haar, tetra, sh"},
                                           BadLobe{"haar_option_on_tetra", "--basis tetra --eps 0.3", "apply to --basis haar"},
                                           BadLobe{"sh_option_on_haar", "--order 4", "--order and --quadrature apply"},
                                           BadLobe{"levels_crossed", "--min-level 9 --max-level 8", "--min-level"},
                                           BadLobe{"unknown_refiner", "--refiner percent", "--refiner"},
                                           BadLobe{"tetra_level_too_high", "--basis tetra --level 11", "--level"}),
                         [](const auto& tp) { return std::string(tp.param.name); });

TEST(LobeCli, WrongSuffixIsRejected) {
  std::string text;
  EXPECT_NE(testutil::runCli("lobe -o lobe.txt", text), 0);
  EXPECT_NE(text.find(".vtp"), std::string::npos) << text;
}

TEST(LobeCli, JsonReportAndVtkSurface) {
  fs::path out = testutil::testDir() / "lobe.vtp";
  fs::remove(out);
  std::string text;
  ASSERT_EQ(testutil::runCli("lobe --exponent 500 --specular 0.6 --diffuse 0.2 --incident-deg 40 --json -o " + out.string(), text), 0)
      << text;
  auto j = nlohmann::json::parse(text);
  for (const char* key : {"coefficients", "bytes", "project_ms", "eval_ns", "l2_rel_error", "max_rel_error", "integral_rel_error"}) {
    ASSERT_TRUE(j.contains(key)) << key;
    EXPECT_TRUE(std::isfinite(j[key].get<double>())) << key;
  }
  EXPECT_LT(j["integral_rel_error"].get<double>(), 0.02);
  vtkNew<vtkXMLPolyDataReader> r;
  r->SetFileName(out.c_str());
  r->Update();
  vtkPolyData* pd = r->GetOutput();
  ASSERT_GT(pd->GetNumberOfPoints(), 30000);
  vtkDataArray* a = pd->GetPointData()->GetArray("intensity");
  ASSERT_NE(a, nullptr);
  ASSERT_NE(pd->GetPointData()->GetArray("analytic_intensity"), nullptr);
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(a->GetComponent(i, c)));
  fs::remove(out);
}

}  // namespace
