// The model lab's reports: the plotted series carry the signed residual where it is (by
// direction, in the hold, per run), the HTML file carries that data and its assets, the
// CLI writes reports without RIG_WEB_ROOT, and a failure never leaves a file behind.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "command.hpp"
#include "comparison.hpp"
#include "html_report.hpp"
#include "lab_test_runs.hpp"
#include "report/report_file.hpp"
#include "report/report_series.hpp"
#include "run_csv.hpp"
#include "test_paths.hpp"

namespace rig::model {
namespace {

using test_runs::simulated_cut;

constexpr double kRetractionOffset_N = 0.02;
constexpr double kHoldSlope_N_per_s = -0.01;

// The same run with a known signed error added: +20 mN while retracting, a -10 mN/s ramp
// during the hold.
RunData with_known_errors(const RunData& run, const Segmentation& seg) {
  RunData out = run;
  for (std::size_t i = 0; i < run.size(); ++i) {
    if (seg.phase[i] == Phase::kRetraction) out.force_N[i] += kRetractionOffset_N;
    if (seg.phase[i] == Phase::kHold)
      out.force_N[i] += kHoldSlope_N_per_s * (run.t_s[i] - run.t_s[seg.hold_begin]);
  }
  return out;
}

double mean_of(const nlohmann::json& values) {
  double sum = 0.0;
  int n = 0;
  for (const auto& v : values) {
    if (v.is_null()) continue;
    sum += v.get<double>();
    ++n;
  }
  return n > 0 ? sum / n : NAN;
}

std::string read_all(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The report's data object, parsed back out of the HTML.
nlohmann::json embedded_data(const std::string& html) {
  const std::string marker = "const report = ";
  const auto at = html.find(marker);
  if (at == std::string::npos) return {};
  const auto end = html.find(";\n", at);
  return nlohmann::json::parse(html.substr(at + marker.size(), end - at - marker.size()));
}

TEST(ReportSeries, CarryTheSignedResidualByDirectionAndInTheHold) {
  const RunData clean = simulated_cut(2.0, 12.0);
  const Comparison cmp = compare(ForceModel::paper_interpreted(), {clean});
  const Segmentation& seg = cmp.runs[0].segmentation;
  ASSERT_GT(seg.hold_end, seg.hold_begin);
  const RunData shifted = with_known_errors(clean, seg);
  const nlohmann::json before = report_series({clean}, cmp, nullptr);
  const nlohmann::json after = report_series({shifted}, cmp, nullptr);
  // Only the retraction moved, by exactly the offset in every bin it covers.
  ASSERT_EQ(before["depth"]["retraction_N"].size(), after["depth"]["retraction_N"].size());
  int bins = 0;
  for (std::size_t b = 0; b < after["depth"]["retraction_N"].size(); ++b) {
    const auto& a = after["depth"]["retraction_N"][b];
    if (a.is_null()) continue;
    EXPECT_NEAR(a.get<double>() - before["depth"]["retraction_N"][b].get<double>(),
                kRetractionOffset_N, 1e-9)
        << "bin " << b;
    ++bins;
  }
  EXPECT_GT(bins, 50) << "retraction from 12 mm covers most bins";
  EXPECT_NEAR(mean_of(after["depth"]["insertion_N"]), mean_of(before["depth"]["insertion_N"]),
              1e-12);
  // The hold trace follows the ramp in time-in-hold.
  ASSERT_EQ(after["hold"].size(), 1U);
  const auto& t = after["hold"][0]["t_s"];
  const auto& r_after = after["hold"][0]["residual_N"];
  const auto& r_before = before["hold"][0]["residual_N"];
  EXPECT_NEAR(t.back().get<double>(), 2.0, 0.1);
  for (std::size_t k = 0; k < t.size(); k += 37) {
    EXPECT_NEAR(r_after[k].get<double>() - r_before[k].get<double>(),
                kHoldSlope_N_per_s * t[k].get<double>(), 1e-9);
  }
  // One small multiple per run, measured and model on the same time axis.
  ASSERT_EQ(after["runs"].size(), 1U);
  EXPECT_EQ(after["runs"][0]["t_s"].size(), after["runs"][0]["measured_N"].size());
  EXPECT_EQ(after["runs"][0]["t_s"].size(), after["runs"][0]["model_N"].size());
  EXPECT_FALSE(after.contains("after"));
}

TEST(HtmlReport, EmbedsThePlottedSeriesAndItsAssets) {
  const RunData run = simulated_cut(1.0, 11.0);
  const Comparison before = compare(ForceModel::paper_interpreted(), {run});
  const Comparison after = compare(ForceModel::paper_interpreted(), {run}, true);
  const ReportAssets assets = find_report_assets(RIG_TEST_BIN_DIR);
  const std::string html =
      render_report({run}, {"fit", &before, &after, nlohmann::json::object()}, assets);
  EXPECT_NE(html.find("function rigLabPlots"), std::string::npos);
  EXPECT_NE(html.find(assets.uplot_js.substr(0, 200)), std::string::npos) << "uPlot is inlined";
  const nlohmann::json data = embedded_data(html);
  ASSERT_TRUE(data.contains("series"));
  EXPECT_EQ(data["kind"], "fit");
  EXPECT_EQ(data["series"], report_series({run}, before, &after))
      << "the file plots exactly the computed series";
  const auto& panel = data["series"]["runs"][0];
  EXPECT_NEAR(panel["after_rmse_N"].get<double>(), after.runs[0].overall.rmse_N, 1e-12);
  EXPECT_LE(panel["after_rmse_N"].get<double>(), panel["rmse_N"].get<double>() + 1e-9)
      << "refitting never makes the overlay worse";
}

TEST(ReportFile, AFailedWriteLeavesNoFileAndKeepsTheOldOne) {
  testing::ScratchDir dir("report-file");
  EXPECT_THROW(write_file_atomically(dir.file("missing/dir/r.html"), "x"), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(dir.file("missing")));
  std::filesystem::create_directories(
      dir.file("taken.html"));  // a directory where the file should go
  EXPECT_THROW(write_file_atomically(dir.file("taken.html"), "x"), std::runtime_error);
  EXPECT_TRUE(std::filesystem::is_directory(dir.file("taken.html")));
  write_file_atomically(dir.file("ok.html"), "first");
  write_file_atomically(dir.file("ok.html"), "second");
  EXPECT_EQ(read_all(dir.file("ok.html")), "second");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 2) << "no temporary files are left behind";
}

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
  ASSERT_EQ(rig("model diagnose " + runs + " --only shaft_friction,sensor_drift --report " +
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
  EXPECT_EQ(diagnosed["lab"]["candidates"].size(), 2U);
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
