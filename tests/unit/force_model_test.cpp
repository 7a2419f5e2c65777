// Eq. 1: as printed (with its defects reported by lint) and our continuous reading.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "force_model.hpp"
#include "model_lint.hpp"
#include "test_paths.hpp"

namespace rig::model {
namespace {

TEST(ForceModel, TheInterpretedModelIsContinuousAndPeaksAtThePuncture) {
  const ForceModel m = ForceModel::load(testing::source("model/params/paper-interpreted.toml"));
  EXPECT_DOUBLE_EQ(m.baseline(0.5, 15), 0.0066 * 0.5);
  EXPECT_NEAR(m.baseline(3.55, 15), 0.0066 * 0.75 + 0.078 * 2.8, 1e-9);  // the peak
  EXPECT_LT(m.baseline(3.7, 15), m.baseline(3.55, 15) - 0.03);           // the drop
  EXPECT_DOUBLE_EQ(m.baseline(9.35, 15), 0.0);
  EXPECT_DOUBLE_EQ(m.baseline(12.0, 15), 0.0);
  for (const auto& f : lint_model(m))
    EXPECT_NE(f.severity, LintFinding::Severity::kError) << f.what;
}

TEST(ForceModel, XpiAndXpfInterpolateInIopAndExtrapolationIsFlagged) {
  const ForceModel m = ForceModel::paper_interpreted();
  EXPECT_NEAR(m.puncture_depth_mm(15.5), 3.65, 1e-12);
  EXPECT_NEAR(m.final_depth_mm(17.5), 9.93, 1e-12);
  EXPECT_FALSE(m.extrapolates(16.0));
  EXPECT_TRUE(m.extrapolates(20.0));
  EXPECT_NEAR(m.puncture_depth_mm(19.0), 4.64, 1e-12);
}

TEST(ModelLint, ThePrintedModelReportsItsMissingValueUnusedNameAndEveryDiscontinuity) {
  const ForceModel m = ForceModel::load(testing::source("model/params/paper-printed.toml"));
  const auto findings = lint_model(m);
  auto has = [&](const std::string& text) {
    for (const auto& f : findings) {
      if (f.what.find(text) != std::string::npos) return true;
    }
    return false;
  };
  EXPECT_TRUE(has("11 names but 10 values"));
  EXPECT_TRUE(has("parameter 'k' is listed but Eq. 1 does not use it"));
  // At IOP 15: a x = 0.00495 N at 0.75 mm, b x - c = 0.1115 N: a jump of +0.1065 N.
  bool toe = false;
  for (const auto& f : findings) {
    if (f.iop_mmHg == 15.0 && std::abs(f.x_mm - 0.75) < 1e-9) {
      toe = true;
      EXPECT_NEAR(f.size_N, 0.078 * 0.75 + 0.053 - 0.0066 * 0.75, 1e-6);
    }
  }
  EXPECT_TRUE(toe);
  EXPECT_TRUE(has("discontinuity at x_pi x = 3.550 mm (IOP 15 mmHg)"));
  EXPECT_TRUE(has("discontinuity at cut end x = 6.890 mm"));
  EXPECT_TRUE(has("discontinuity at x_pf x = 9.350 mm"));
}

TEST(ModelFile, AnUnknownKeyNamesFileLineAndKey) {
  testing::ScratchDir dir("modelfile");
  std::ofstream(dir.file("m.toml")) << "[model]\nname = \"x\"\n[parameters]\na = 0.1\nbb = 2\n";
  try {
    ForceModel::load(dir.file("m.toml"));
    FAIL();
  } catch (const ModelFileError& e) {
    EXPECT_NE(std::string(e.what()).find("m.toml:5: key 'parameters.bb': unknown key"),
              std::string::npos)
        << e.what();
  }
}

// Found while fuzzing (issue 14): POST /api/model names a file; /dev/zero kept the parser
// reading forever on the API's thread.
TEST(ModelFile, ADeviceADirectoryOrAMissingFileIsRefusedBeforeReadingNamingThePath) {
  testing::ScratchDir dir("modelfile-kind");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"/dev/zero", "not a regular file"},
      {dir.path().string(), "not a regular file"},
      {dir.file("none.toml"), "no such model file"}};
  for (const auto& [path, why] : cases) {
    try {
      ForceModel::load(path);
      ADD_FAILURE() << path << " was loaded";
    } catch (const ModelFileError& e) {
      EXPECT_NE(std::string(e.what()).find(path + ": " + why), std::string::npos) << e.what();
    }
  }
}

// Found while fuzzing (CI, fuzz.model_file): a final depth of 1e9 mm kept lint scanning in
// 0.01 mm steps past the timeout; an infinite depth was read as a number.
TEST(ModelFile, ADepthNoEyeHasOrANonFiniteTableValueIsRefusedNamingTheKey) {
  testing::ScratchDir dir("modelfile-depth");
  const std::string table =
      "[model]\nname = \"x\"\n[table]\niop_mmHg = [15.0, 18.0]\nx_pi_mm = [3.5, 3.8]\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {table + "x_pf_mm = [9.0, 1e9]\n", "key 'table.x_pf_mm': a depth outside 0..100 mm"},
      {table + "x_pf_mm = [9.0, inf]\n", "key 'table.x_pf_mm': not a finite number"},
      {table + "x_pf_mm = [9.0, -1.0]\n", "key 'table.x_pf_mm': a depth outside 0..100 mm"},
      {table + "x_pf_mm = [9.0, 9.5]\n[parameters]\nx_pf_shift = -500.0\n",
       "key 'parameters.x_pf_shift': a shift beyond +-100 mm"}};
  for (const auto& [text, why] : cases) {
    std::ofstream(dir.file("m.toml"), std::ios::trunc) << text;
    try {
      ForceModel::load(dir.file("m.toml"));
      ADD_FAILURE() << text << " was loaded";
    } catch (const ModelFileError& e) {
      EXPECT_NE(std::string(e.what()).find(dir.file("m.toml") + ":"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  }
}

TEST(ModelLint, ANegativeForceIsScannedToTheEndOfAModelOneHundredMillimetresDeep) {
  ForceModel m = ForceModel::load(testing::source("model/params/paper-printed.toml"));
  m.table.x_pf_mm.assign(m.table.x_pf_mm.size(),
                         100.0);  // the printed unloading piece runs on below zero
  double deepest_mm = 0.0;
  for (const auto& f : lint_model(m)) {
    double from_mm = 0.0, to_mm = 0.0;
    if (std::sscanf(f.what.c_str(), "negative force from x = %lf to %lf mm", &from_mm, &to_mm) == 2)
      deepest_mm = std::max(deepest_mm, to_mm);
  }
  EXPECT_GT(deepest_mm, 99.9);
}

TEST(ModelFile, SavingAndLoadingKeepsParametersAndEffects) {
  testing::ScratchDir dir("modelsave");
  ForceModel m = ForceModel::paper_interpreted();
  m.params.b = 0.09;
  m.effects.push_back({"shaft_friction", {{"mu_N_per_mm", 0.006}}});
  m.save(dir.file("saved.toml"));
  const ForceModel back = ForceModel::load(dir.file("saved.toml"));
  EXPECT_DOUBLE_EQ(back.params.b, 0.09);
  ASSERT_EQ(back.effects.size(), 1U);
  EXPECT_DOUBLE_EQ(back.effects[0].params.at("mu_N_per_mm"), 0.006);
}

}  // namespace
}  // namespace rig::model
