// The paper's model handled straight: lint reports the printed unloading piece's negative
// force and offers the reading without the stray k; a printed-form file is run as printed
// (with a warning) or refused, never silently as our continuous reading; the numbers of
// docs/model.md's argument for g0 are what the model computes.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

#include "command.hpp"
#include "comparison.hpp"
#include "diagnosis.hpp"
#include "lab_test_runs.hpp"
#include "model_fit.hpp"
#include "model_lint.hpp"
#include "test_paths.hpp"

namespace rig::model {
namespace {

ForceModel printed() {
  return ForceModel::load(testing::source("model/params/paper-printed.toml"));
}
ForceModel printed_without_k() {
  return ForceModel::load(testing::source("model/params/paper-printed-without-k.toml"));
}

const LintFinding* finding(const std::vector<LintFinding>& findings, const std::string& text,
                           double iop = -1.0) {
  for (const auto& f : findings) {
    if (f.what.find(text) != std::string::npos && (iop < 0.0 || f.iop_mmHg == iop)) return &f;
  }
  return nullptr;
}

TEST(Lint, ReportsThePrintedUnloadingPiecesNegativeForce) {
  const auto findings = lint_model(printed());
  const LintFinding* negative = finding(findings, "negative force", 15.0);
  ASSERT_NE(negative, nullptr);
  EXPECT_EQ(negative->severity, LintFinding::Severity::kError);
  // Read positionally the unloading piece is h x + m = -0.08 x + 0.02: -0.53 N at 6.89 mm,
  // -0.73 N just before x_pf = 9.35 mm.
  EXPECT_NEAR(negative->lowest_N, -0.08 * 9.34 + 0.02, 0.002);
  EXPECT_EQ(negative->size_N, 0.0) << "not a jump";
  EXPECT_GT(negative->x_mm, 6.89);
  EXPECT_LT(negative->x_mm, 9.35);
  const auto ours = lint_model(ForceModel::paper_interpreted());
  EXPECT_EQ(finding(ours, "negative force"), nullptr);
}

TEST(Lint, OffersTheReadingWithoutTheStrayKBesideThePositionalOne) {
  const ForceModel positional = printed();
  const auto alternative = reading_without_k(positional);
  ASSERT_TRUE(alternative.has_value());
  EXPECT_EQ(alternative->printed.names.size(), 10U);
  EXPECT_EQ(alternative->printed.values.size(), 10U);
  EXPECT_DOUBLE_EQ(alternative->printed.value("h"), -0.08);
  EXPECT_DOUBLE_EQ(alternative->printed.value("m"), 0.659);
  EXPECT_DOUBLE_EQ(alternative->printed.value("n"), 0.02);
  // The shipped third file is exactly that reading.
  const ForceModel file = printed_without_k();
  EXPECT_EQ(file.printed.names, alternative->printed.names);
  EXPECT_EQ(file.printed.values, alternative->printed.values);
  // Its unloading is positive: +0.408 N at 6.89 mm to +0.211 N at x_pf (IOP 15 mmHg).
  EXPECT_NEAR(file.baseline(6.90, 15.0), -0.08 * 6.90 + 0.659 + 0.3, 1e-9);
  EXPECT_NEAR(file.baseline(9.34, 15.0), -0.08 * 9.34 + 0.659 + 0.3, 1e-9);
  const auto file_findings = lint_model(file);
  EXPECT_EQ(finding(file_findings, "negative force"), nullptr);
  EXPECT_EQ(finding(file_findings, "names but"), nullptr);
  const auto positional_findings = lint_model(positional);
  const LintFinding* offer = finding(positional_findings, "reading without the stray k");
  ASSERT_NE(offer, nullptr);
  EXPECT_NE(offer->what.find("+0.4078 N"), std::string::npos) << offer->what;
  EXPECT_NE(offer->what.find("-0.5312 N"), std::string::npos) << offer->what;
  EXPECT_FALSE(reading_without_k(file).has_value()) << "nothing left to drop";
}

TEST(PrintedForm, CompareRunsItAsPrintedAndSaysSo) {
  const RunData run = test_runs::simulated_cut(0.0, 12.0);
  for (const ForceModel& m : {printed(), printed_without_k()}) {
    const Comparison c = compare(m, {run});
    bool warned = false;
    for (const auto& w : c.warnings)
      warned = warned || w.find("evaluated as printed") != std::string::npos;
    EXPECT_TRUE(warned) << m.name;
    for (std::size_t i = 0; i < run.size(); i += 97) {
      if (c.runs[0].segmentation.phase[i] == Phase::kApproach ||
          i > c.runs[0].segmentation.insertion_end)
        continue;
      EXPECT_NEAR(c.runs[0].prediction[i], m.baseline(run.x_mm[i], run.x_mm[i], 15.0), 1e-9)
          << m.name << " at x = " << run.x_mm[i];
    }
  }
  // At 8 mm the two readings differ by m + n P - 0.02 = 0.939 N: which file ran shows.
  EXPECT_NEAR(printed_without_k().baseline(8.0, 15.0) - printed().baseline(8.0, 15.0),
              0.659 + 0.3 - 0.02, 1e-9);
}

TEST(PrintedForm, IsRefusedWhereTheLabWouldFitItsParameters) {
  const std::vector<RunData> runs = {test_runs::simulated_cut(0.0, 11.0)};
  EXPECT_THROW(compare(printed(), runs, true), ModelFileError);
  EXPECT_THROW(diagnose(printed(), runs), ModelFileError);
  EXPECT_THROW(fit_model(printed(), runs, {"shaft_friction"}), ModelFileError);
  try {
    fit_model(printed_without_k(), runs, {});
    FAIL() << "a printed-form file was fitted";
  } catch (const ModelFileError& e) {
    EXPECT_NE(std::string(e.what()).find("eq1-printed"), std::string::npos) << e.what();
  }
}

TEST(PrintedForm, TheCliRefusesDiagnoseAndFitNamingTheFile) {
  testing::ScratchDir dir("printed-cli");
  ASSERT_EQ(testing::run_command(testing::bin("rig") + " sim generate --out " + dir.file("runs") +
                                 " --iops 15 --velocities 2 --depth 11")
                .exit_code,
            0);
  const std::string file = testing::source("model/params/paper-printed.toml");
  for (const std::string command : {"diagnose", "fit"}) {
    const auto r = testing::run_command(testing::bin("rig") + " model " + command + " " +
                                        dir.file("runs") + " --model " + file);
    EXPECT_NE(r.exit_code, 0) << command;
    EXPECT_NE(r.output.find("paper-printed.toml"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("eq1-printed"), std::string::npos) << r.output;
  }
  const auto compared = testing::run_command(testing::bin("rig") + " model compare " +
                                             dir.file("runs") + " --model " + file);
  EXPECT_EQ(compared.exit_code, 0);
  EXPECT_NE(compared.output.find("evaluated as printed"), std::string::npos) << compared.output;
}

// docs/model.md, "The offset g0, compared like with like": every number it quotes.
TEST(OffsetG0, TheDocsCompareLikeWithLike) {
  const ForceModel as_printed = printed(), ours = ForceModel::paper_interpreted();
  const double x_pi = 3.55, iop = 15.0;
  EXPECT_NEAR(as_printed.baseline(x_pi - 1e-9, iop), 0.330, 0.0005)
      << "pre-cut peak with c as printed";
  EXPECT_NEAR(as_printed.baseline(x_pi + 1e-9, iop), 0.298, 0.0005)
      << "printed cutting piece at x_pi";
  EXPECT_NEAR(as_printed.baseline(0.75 + 1e-9, iop) - as_printed.baseline(0.75 - 1e-9, iop), 0.107,
              0.0005)
      << "step at 0.75 mm";
  EXPECT_NEAR(ours.baseline(x_pi - 1e-9, iop), 0.223, 0.0005)
      << "pre-cut peak with c's sign corrected";
  EXPECT_NEAR(cutting_plateau(ours.params, x_pi + ours.params.w_drop, iop) - ours.params.g0, 0.298,
              0.002)
      << "the same printed piece";
  EXPECT_NEAR(ours.baseline(x_pi + ours.params.w_drop + 1e-6, iop), 0.183, 0.0005)
      << "our plateau after the drop";
  // The shift that would keep the printed drop: the sign correction's -0.107 N; ours is -0.114 N.
  const double correction =
      (ours.baseline(x_pi - 1e-9, iop) - as_printed.baseline(x_pi - 1e-9, iop));
  EXPECT_NEAR(correction, -0.107, 0.0005);
  EXPECT_NEAR(ours.params.g0 - correction, -0.007, 0.0005);
}

}  // namespace
}  // namespace rig::model
