// The CLI's --report on compare, diagnose and fit: written without RIG_WEB_ROOT (the page's
// assets come from the build tree), carrying the plotted series, and no file on failure.
// Runs the built `rig` (simulate, fit): label lab, release tree.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "command.hpp"
#include "report_test_helpers.hpp"
#include "test_paths.hpp"

namespace rig::model {
namespace {

class ReportCli : public ::testing::Test {
 protected:
  void SetUp() override {
    unsetenv("RIG_WEB_ROOT");  // a fresh checkout's build tree, nothing configured
    ASSERT_EQ(testing::run_command(
                  testing::bin("rig") + " sim generate --out " + dir_.file("runs") +
                  " --effect shaft_friction --iops 15,18 --velocities 2 --depth 11 --hold 1")
                  .exit_code,
              0);
  }
  testing::CommandResult rig(const std::string& args) {
    return testing::run_command(testing::bin("rig") + " " + args);
  }
  testing::ScratchDir dir_{"report-cli"};
};

TEST_F(ReportCli, CompareDiagnoseAndFitWriteReportsWithoutRigWebRoot) {
  const std::string runs = dir_.file("runs");
  ASSERT_EQ(rig("model compare " + runs + " --report " + dir_.file("compare.html")).exit_code, 0);
  ASSERT_EQ(rig("model diagnose " + runs + " --only shaft_friction --report " +
                dir_.file("diagnose.html"))
                .exit_code,
            0);
  ASSERT_EQ(rig("model fit " + runs + " --add shaft_friction --report " + dir_.file("fit.html"))
                .exit_code,
            0);
  const nlohmann::json compared = embedded_data(read_all(dir_.file("compare.html")));
  const nlohmann::json diagnosed = embedded_data(read_all(dir_.file("diagnose.html")));
  const nlohmann::json fitted = embedded_data(read_all(dir_.file("fit.html")));
  EXPECT_EQ(compared["series"]["runs"].size(), 2U);
  EXPECT_EQ(compared["series"]["hold"].size(), 2U);
  EXPECT_EQ(diagnosed["lab"]["candidates"].size(), 1U);
  EXPECT_EQ(diagnosed["series"]["runs"].size(), 2U);
  ASSERT_TRUE(fitted["series"].contains("after"));
  // Friction: the refitted baseline's residual parts by direction (+ inserting, - retracting),
  // the fitted model's much less.
  const auto& depth = fitted["series"]["depth"];
  const double gap_before = mean_of(depth["insertion_N"]) - mean_of(depth["retraction_N"]);
  const double gap_after =
      mean_of(depth["after_insertion_N"]) - mean_of(depth["after_retraction_N"]);
  EXPECT_GT(gap_before, 0.003) << "friction pushes back inserting and pulls retracting";
  EXPECT_LT(std::abs(gap_after), 0.5 * gap_before);
  for (const auto& panel : fitted["series"]["runs"])
    EXPECT_LT(panel["after_rmse_N"].get<double>(), panel["rmse_N"].get<double>());
}

TEST_F(ReportCli, AFailedReportLeavesNoFile) {
  const auto missing_run =
      rig("model compare " + dir_.file("no-such-run.csv") + " --report " + dir_.file("a.html"));
  EXPECT_NE(missing_run.exit_code, 0);
  EXPECT_FALSE(std::filesystem::exists(dir_.file("a.html")));
  const auto bad_folder =
      rig("model compare " + dir_.file("runs") + " --report " + dir_.file("nowhere/b.html"));
  EXPECT_NE(bad_folder.exit_code, 0);
  EXPECT_NE(bad_folder.output.find("nowhere/b.html"), std::string::npos) << bad_folder.output;
  std::ofstream(dir_.file("old.html")) << "old report";
  const auto printed_refit = rig("model compare " + dir_.file("runs") + " --refit --model " +
                                 testing::source("model/params/paper-printed.toml") + " --report " +
                                 dir_.file("old.html"));
  EXPECT_NE(printed_refit.exit_code, 0);
  EXPECT_EQ(read_all(dir_.file("old.html")), "old report") << "the old file is untouched";
}

}  // namespace
}  // namespace rig::model
