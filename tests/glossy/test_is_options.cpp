// configure() of the Illumination Samples extension, table-driven: every accepted combination lands
// in the basis it names, and every bad value or misplaced option is refused with a message that names
// the option (and says why), like `glossyhr lobe` does.
#include <gtest/gtest.h>

#include <cmath>

#include "fake_host.h"

namespace {

using Options = std::vector<hr::OptionValue>;

TEST(IsOptions, DefaultsAreThePapersSolvingSettings) {
  auto ext = testhost::configured();
  const glossy::BasisSpec& b = ext->basis();
  EXPECT_EQ(b.basis, glossy::Basis::Haar);
  EXPECT_EQ(b.haar.eps, 0.5);
  EXPECT_EQ(b.haar.minLevel, 1);
  EXPECT_EQ(b.haar.maxLevel, 3);
  EXPECT_EQ(b.haar.refiner, glossy::Refiner::Relative);
  EXPECT_EQ(ext->name(), "is");
  std::vector<std::string> names;
  for (const auto& o : ext->options()) names.push_back(o.name);
  EXPECT_EQ(names, (std::vector<std::string>{"basis", "dir-eps", "dir-min-level", "dir-max-level", "tetra-level", "sh-order",
                                             "reflection-refine", "sender-extent", "exact-highlights"}));
}

/// What the host's oracle is told of a material (docs/glossy.md, "The reflection term"): the lobe's
/// 1/e half-width sqrt(2/n) and the specular albedo's luminance; nothing for a material it does not
/// simulate or with --reflection-refine off.
TEST(IsOptions, ReflectorGivesTheLobesWidthUnlessTurnedOff) {
  const hr::MaterialInfo glossyMat{hr::Rgb(0.2), hr::Rgb(0.6), 300.0, hr::Rgb(0.0)};
  const hr::MaterialInfo diffuseMat{hr::Rgb(0.7), hr::Rgb(0.0), 1.0, hr::Rgb(0.0)};
  auto on = testhost::configured();
  const hr::Reflector r = on->reflector(glossyMat);
  EXPECT_NEAR(r.width, std::sqrt(2.0 / 300.0), 1e-12);
  EXPECT_NEAR(r.albedo, 0.6, 1e-9);
  EXPECT_EQ(on->reflector(diffuseMat).albedo, 0.0);
  auto off = testhost::configured({{"reflection-refine", "off"}});
  EXPECT_EQ(off->reflector(glossyMat).albedo, 0.0);
  // cell: the wider of the lobe and the material's Haar cell, pi/2 / 2^level. n = 300 gets level 4
  // (5.6 degrees, wider than its 4.7-degree lobe); at a given level 8 the lobe is the wider.
  auto cell = testhost::configured({{"reflection-refine", "cell"}});
  EXPECT_NEAR(cell->reflector(glossyMat).width, 0.5 * M_PI / 16.0, 1e-12);
  EXPECT_NEAR(cell->reflector(glossyMat).albedo, 0.6, 1e-9);
  auto fine = testhost::configured({{"reflection-refine", "cell"}, {"dir-max-level", "8"}});
  EXPECT_NEAR(fine->reflector(glossyMat).width, std::sqrt(2.0 / 300.0), 1e-12);
  auto tetra = testhost::configured({{"reflection-refine", "cell"}, {"basis", "tetra"}});
  EXPECT_NEAR(tetra->reflector(glossyMat).width, std::sqrt(2.0 / 300.0), 1e-12);
}

TEST(IsOptions, AcceptedValues) {
  struct Row {
    Options in;
    glossy::Basis basis;
    double eps;
    int minLevel, maxLevel, tetraLevel, shOrder;
  };
  const Row rows[] = {
      {{}, glossy::Basis::Haar, 0.5, 1, 3, 3, 8},
      {{{"basis", "haar"}, {"dir-eps", "0.1"}}, glossy::Basis::Haar, 0.1, 1, 3, 3, 8},
      {{{"dir-min-level", "0"}, {"dir-max-level", "8"}}, glossy::Basis::Haar, 0.5, 0, 8, 3, 8},
      {{{"dir-min-level", "2"}, {"dir-max-level", "2"}}, glossy::Basis::Haar, 0.5, 2, 2, 3, 8},
      {{{"dir-eps", "1e-3"}, {"dir-max-level", "5"}}, glossy::Basis::Haar, 1e-3, 1, 5, 3, 8},
      {{{"basis", "tetra"}}, glossy::Basis::Tetra, 0.5, 1, 3, 3, 8},
      {{{"basis", "tetra"}, {"tetra-level", "0"}}, glossy::Basis::Tetra, 0.5, 1, 3, 0, 8},
      {{{"basis", "tetra"}, {"tetra-level", "8"}}, glossy::Basis::Tetra, 0.5, 1, 3, 8, 8},
      {{{"basis", "sh"}, {"sh-order", "1"}}, glossy::Basis::Sh, 0.5, 1, 3, 3, 1},
      {{{"sh-order", "32"}, {"basis", "sh"}}, glossy::Basis::Sh, 0.5, 1, 3, 3, 32},
  };
  for (const Row& r : rows) {
    std::string what;
    for (const auto& o : r.in) what += " --" + o.name + " " + o.value;
    auto ext = testhost::configured(r.in);
    const glossy::BasisSpec& b = ext->basis();
    EXPECT_EQ(b.basis, r.basis) << what;
    EXPECT_EQ(b.haar.eps, r.eps) << what;
    EXPECT_EQ(b.haar.minLevel, r.minLevel) << what;
    EXPECT_EQ(b.haar.maxLevel, r.maxLevel) << what;
    EXPECT_EQ(b.tetraLevel, r.tetraLevel) << what;
    EXPECT_EQ(b.shOrder, r.shOrder) << what;
  }
}

TEST(IsOptions, RefusedValuesNameTheOption) {
  struct Row {
    Options in;
    const char* message;  // the whole message
  };
  const Row rows[] = {
      {{{"basis", "wavelet"}}, "--basis: unknown basis 'wavelet' (valid: haar, tetra, sh, auto)"},
      {{{"basis", ""}}, "--basis: unknown basis '' (valid: haar, tetra, sh, auto)"},
      {{{"basis", "Auto"}}, "--basis: unknown basis 'Auto' (valid: haar, tetra, sh, auto)"},
      {{{"dir-eps", "-1"}}, "--dir-eps: must be > 0, got -1"},
      {{{"dir-eps", "0"}}, "--dir-eps: must be > 0, got 0"},
      {{{"dir-eps", "abc"}}, "--dir-eps: not a finite number: 'abc'"},
      {{{"dir-eps", "0.5x"}}, "--dir-eps: not a finite number: '0.5x'"},
      {{{"dir-eps", "nan"}}, "--dir-eps: not a finite number: 'nan'"},
      {{{"dir-eps", "inf"}}, "--dir-eps: not a finite number: 'inf'"},
      {{{"dir-eps", "1e999"}}, "--dir-eps: not a finite number: '1e999'"},
      {{{"dir-min-level", "-1"}}, "--dir-min-level: must be an integer from 0 to 8, got '-1'"},
      {{{"dir-max-level", "9"}}, "--dir-max-level: must be an integer from 0 to 8, got '9'"},
      {{{"dir-max-level", "3.0"}}, "--dir-max-level: must be an integer from 0 to 8, got '3.0'"},
      {{{"dir-min-level", "4"}}, "--dir-min-level: --dir-min-level (4) must not exceed --dir-max-level (3)"},
      {{{"dir-max-level", "0"}}, "--dir-max-level: --dir-min-level (1) must not exceed --dir-max-level (0)"},
      {{{"tetra-level", "4"}}, "--tetra-level: applies to --basis tetra only (the basis is haar)"},
      {{{"basis", "tetra"}, {"dir-eps", "0.2"}}, "--dir-eps: applies to --basis haar only (the basis is tetra)"},
      {{{"basis", "sh"}, {"dir-max-level", "4"}}, "--dir-max-level: applies to --basis haar only (the basis is sh)"},
      {{{"basis", "sh"}, {"tetra-level", "2"}}, "--tetra-level: applies to --basis tetra only (the basis is sh)"},
      {{{"sh-order", "4"}}, "--sh-order: applies to --basis sh only (the basis is haar)"},
      {{{"basis", "tetra"}, {"tetra-level", "9"}}, "--tetra-level: must be an integer from 0 to 8, got '9'"},
      {{{"basis", "sh"}, {"sh-order", "0"}}, "--sh-order: must be an integer from 1 to 32, got '0'"},
      {{{"basis", "sh"}, {"sh-order", "33"}}, "--sh-order: must be an integer from 1 to 32, got '33'"},
      {{{"dir-eps", "0.1"}, {"dir-eps", "0.2"}}, "--dir-eps: given twice"},
      {{{"reflection-refine", "yes"}}, "--reflection-refine: must be on, cell or off, got 'yes'"},
      {{{"reflection-refine", "on"}, {"reflection-refine", "off"}}, "--reflection-refine: given twice"},
      {{{"sender-extent", "yes"}}, "--sender-extent: must be on or off, got 'yes'"},
      {{{"sender-extent", "on"}, {"sender-extent", "off"}}, "--sender-extent: given twice"},
      {{{"eps", "0.1"}},
       "--eps: not an option of --algorithm is (valid: basis, dir-eps, dir-min-level, dir-max-level, tetra-level, sh-order, "
       "reflection-refine, sender-extent, exact-highlights)"},
  };
  for (const Row& r : rows) {
    glossy::IlluminationSamples ext;
    try {
      ext.configure(r.in);
      ADD_FAILURE() << "accepted: " << r.message;
    } catch (const hr::InputError& e) {
      EXPECT_EQ(std::string(e.what()), r.message);
    }
  }
}

}  // namespace
