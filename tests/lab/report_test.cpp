// The model lab's reports: the plotted series carry the signed residual where it is (by
// direction, in the hold, per run), the HTML file carries that data and its assets, and a
// failed write never leaves a file behind. (The CLI's --report: report_cli_test.cpp.)
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
#include "report_test_helpers.hpp"
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

}  // namespace
}  // namespace rig::model
