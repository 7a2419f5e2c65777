// Eq. 1: as printed (with its defects reported by lint) and our continuous reading.
#include <gtest/gtest.h>

#include <cmath>
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
  EXPECT_LT(m.baseline(3.7, 15), m.baseline(3.55, 15) - 0.03);          // the drop
  EXPECT_DOUBLE_EQ(m.baseline(9.35, 15), 0.0);
  EXPECT_DOUBLE_EQ(m.baseline(12.0, 15), 0.0);
  for (const auto& f : lint_model(m)) EXPECT_NE(f.severity, LintFinding::Severity::kError) << f.what;
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
    EXPECT_NE(std::string(e.what()).find("m.toml:5: key 'parameters.bb': unknown key"), std::string::npos) << e.what();
  }
}

// Found while fuzzing (issue 14): POST /api/model names a file; /dev/zero kept the parser
// reading forever on the API's thread.
TEST(ModelFile, ADeviceADirectoryOrAMissingFileIsRefusedBeforeReadingNamingThePath) {
  testing::ScratchDir dir("modelfile-kind");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"/dev/zero", "not a regular file"}, {dir.path().string(), "not a regular file"}, {dir.file("none.toml"), "no such model file"}};
  for (const auto& [path, why] : cases) {
    try {
      ForceModel::load(path);
      ADD_FAILURE() << path << " was loaded";
    } catch (const ModelFileError& e) {
      EXPECT_NE(std::string(e.what()).find(path + ": " + why), std::string::npos) << e.what();
    }
  }
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
