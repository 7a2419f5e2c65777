// Measured real data (tests/data/iaquinta2023-meat-indentation/README.md): four indentations
// of raw meat at 1 mm/s, each followed by a ~10 s hold of the crosshead in which the force
// relaxes to about half. Sampled by a testing machine at 10 Hz, so - unlike the digitized
// needle curve - not digitized: the instrument candidates stay candidates, yet none may be
// the verdict; the lab must say that Eq. 1 (ovine cornea under a keratome) does not describe
// meat; and the relaxation must show in the hold's signed residual. What depends on the
// effect families' fits (the verdict, the relaxation fit) is in
// real_data_meat_expectations_test.cpp (label lab).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "comparison.hpp"
#include "data_checks.hpp"
#include "diagnosis.hpp"
#include "report/report_series.hpp"
#include "run_csv.hpp"
#include "test_paths.hpp"

#include <nlohmann/json.hpp>

namespace rig::model {
namespace {

struct MeatRun {
  const char* file;
  double depth_mm;  // where the crosshead holds
};

// Depths from the source workbooks' crosshead travel at the start of the hold [mm].
constexpr MeatRun kRuns[] = {
    {"230327-RDG15A-indent-6mm-hold.csv", 6.00},
    {"230327-FF1-1A-indent-6.8mm-hold.csv", 6.80},
    {"230331-FF2-2A-indent-to-1N-hold.csv", 8.38},
    {"230331-RDG1-1D-indent-to-1N-hold.csv", 5.76},
};

RunData meat(const MeatRun& r) {
  return read_run_csv(
      testing::source(std::string("tests/data/iaquinta2023-meat-indentation/") + r.file));
}

std::vector<RunData> all_meat() {
  std::vector<RunData> runs;
  for (const MeatRun& r : kRuns) runs.push_back(meat(r));
  return runs;
}

bool any_contains(const std::vector<std::string>& texts, const std::string& part) {
  return std::any_of(texts.begin(), texts.end(),
                     [&](const std::string& t) { return t.find(part) != std::string::npos; });
}

bool is_instrument(const std::string& effect) {
  return effect == "spatial_ripple" || effect == "mains_interference" || effect == "stick_slip" ||
         effect == "sensor_drift";
}

TEST(MeatIndentationData, ImportsFourRunsEachAnIndentationThenATenSecondHoldWithoutRetraction) {
  for (const MeatRun& r : kRuns) {
    const RunData run = meat(r);
    ASSERT_GT(run.size(), 150U) << r.file;
    const Segmentation s = detect_phases(run);
    EXPECT_NEAR(s.max_depth_mm, r.depth_mm, 0.01) << r.file;
    ASSERT_GT(s.hold_end, s.hold_begin) << r.file << ": the crosshead holds at depth";
    EXPECT_GT(run.t_s[s.hold_end - 1] - run.t_s[s.hold_begin], 9.5) << r.file;
    EXPECT_EQ(s.phase.back(), Phase::kHold) << r.file << ": no retraction was recorded";
    EXPECT_FALSE(s.punctured) << r.file << ": an indenter does not puncture (x_pi " << s.x_pi_mm
                              << " mm)";
    for (std::size_t i = s.hold_begin; i < s.hold_end; ++i)
      ASSERT_NEAR(run.x_mm[i], s.max_depth_mm, 0.01) << r.file << ": held at depth";
  }
}

TEST(MeatIndentationData, IsMeasuredNotDigitizedYetNoInstrumentEffectBecomesTheVerdict) {
  for (const MeatRun& r : kRuns) {
    const SamplingCheck check = check_sampling(meat(r));
    EXPECT_FALSE(check.digitized) << r.file << ": " << check.why;
  }
  DiagnoseOptions only;
  only.only = {"spatial_ripple", "mains_interference", "stick_slip"};
  const Diagnosis d = diagnose(ForceModel::paper_interpreted(), all_meat(), only);
  ASSERT_EQ(d.candidates.size(), 3U);
  for (const CandidateResult& c : d.candidates) {
    std::printf("meat: %s applicable %d gain %.1f %% significant %d: %s%s\n", c.effect.c_str(),
                c.applicable, c.gain_pct, c.significant, c.evidence.c_str(),
                c.not_applicable.c_str());
    EXPECT_EQ(c.not_applicable.find("digitized"), std::string::npos) << c.not_applicable;
    if (c.effect == "spatial_ripple") {
      // A DAQ's regular samples may carry a ripple (no sampling rule against it), but its
      // best period on 6-8.4 mm ramps (3.8-3.9 mm) repeats under 3 times: a bent misfit.
      EXPECT_FALSE(c.applicable) << c.evidence;
      EXPECT_NE(c.not_applicable.find("repeats only"), std::string::npos) << c.not_applicable;
    }
    if (c.effect == "mains_interference") {
      EXPECT_FALSE(c.applicable) << "10 Hz sampling cannot show 50/60 Hz";
    }
  }
  std::printf("meat: verdict among the instrument candidates: %s\n", d.verdict.c_str());
  EXPECT_FALSE(is_instrument(d.verdict)) << d.verdict;
  EXPECT_FALSE(any_contains(d.warnings, "digitized")) << "measured data are not called digitized";
}

TEST(MeatIndentationData, WarnsThatTheCorneaModelDoesNotDescribeMeat) {
  const ForceModel model = ForceModel::paper_interpreted();
  const Comparison refitted = compare(model, all_meat(), true);
  const auto warnings = base_misfit_warnings(model, refitted);
  std::printf("meat: refitted Eq. 1 R^2 %.3f, RMSE %.4f N\n", refitted.overall.r2,
              refitted.overall.rmse_N);
  for (const std::string& w : warnings) std::printf("meat: warning: %s\n", w.c_str());
  EXPECT_TRUE(any_contains(warnings, "does not describe these data"))
      << "R^2 " << refitted.overall.r2;
  EXPECT_TRUE(any_contains(warnings, "puncture")) << "an indentation has no puncture";
}

// Mean of `values` over the samples whose time lies in [from, to) [same unit as values].
double mean_between(const nlohmann::json& t, const nlohmann::json& values, double from, double to) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double ts = t[i].get<double>();
    if (ts < from || ts >= to || values[i].is_null()) continue;
    sum += values[i].get<double>();
    ++n;
  }
  return n > 0 ? sum / n : 0.0;
}

TEST(MeatIndentationData, TheSignedResidualFallsThroughEveryHoldAsTheForceRelaxes) {
  const std::vector<RunData> runs = all_meat();
  const Comparison refitted = compare(ForceModel::paper_interpreted(), runs, true);
  const nlohmann::json hold = report_series(runs, refitted, nullptr)["hold"];
  ASSERT_EQ(hold.size(), runs.size()) << "every run has a hold trace";
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const Segmentation& s = refitted.runs[r].segmentation;
    const double measured_drop = runs[r].force_N[s.hold_begin] - runs[r].force_N[s.hold_end - 1];
    const double early = mean_between(hold[r]["t_s"], hold[r]["residual_N"], 0.0, 1.0);
    const double late = mean_between(hold[r]["t_s"], hold[r]["residual_N"], 9.0, 11.0);
    std::printf(
        "meat %s: force %.3f -> %.3f N in the hold; signed residual first 1 s %+.4f N, "
        "9-11 s %+.4f N\n",
        kRuns[r].file, runs[r].force_N[s.hold_begin], runs[r].force_N[s.hold_end - 1], early, late);
    EXPECT_GT(measured_drop, 0.4 * runs[r].force_N[s.hold_begin])
        << kRuns[r].file << ": the meat relaxes by more than 40 % in 10 s";
    EXPECT_GT(early - late, 0.5 * measured_drop)
        << kRuns[r].file << ": at a held depth Eq. 1 predicts a steady force";
  }
}

}  // namespace
}  // namespace rig::model
