// Real data the project did not generate (tests/data/*/README.md): imported, segmented and
// read honestly - digitized curves get no instrument effect on their digitization steps,
// and the lab says when the cornea model does not describe the tissue.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "comparison.hpp"
#include "data_checks.hpp"
#include "diagnosis.hpp"
#include "lab_test_runs.hpp"
#include "run_csv.hpp"
#include "test_paths.hpp"

namespace rig::model {
namespace {

RunData needle() {
  return read_run_csv(
      testing::source("tests/data/okamura2004-needle/needle-liver-insert-hold-retract.csv"));
}

bool any_contains(const std::vector<std::string>& texts, const std::string& part) {
  return std::any_of(texts.begin(), texts.end(),
                     [&](const std::string& t) { return t.find(part) != std::string::npos; });
}

TEST(NeedleData, ImportsAndSegmentsIntoInsertionHoldAndRetraction) {
  const RunData run = needle();
  ASSERT_GT(run.size(), 800U);
  const Segmentation s = detect_phases(run);
  EXPECT_NEAR(s.max_depth_mm, 30.1, 0.2) << "the needle goes 30 mm deep (digitized value x 100)";
  // The insertion ends where the needle arrived at depth (~2.0-2.4 s), not at the digitized
  // position's largest value, which comes 1.2 s later in the hold.
  EXPECT_NEAR(run.x_mm[s.insertion_end], s.max_depth_mm, 0.1);
  EXPECT_LT(run.t_s[s.insertion_end], 2.5);
  ASSERT_GT(s.hold_end, s.hold_begin) << "the liver data holds at depth";
  EXPECT_EQ(s.hold_begin, s.insertion_end);
  EXPECT_GT(run.t_s[s.hold_end - 1] - run.t_s[s.hold_begin], 5.0);
  EXPECT_EQ(s.phase.back(), Phase::kRetraction);
  for (std::size_t i = s.hold_begin; i < s.hold_end; ++i)
    ASSERT_NEAR(run.x_mm[i], s.max_depth_mm, 0.25) << "held at depth";
}

TEST(NeedleData, IsRecognisedAsDigitizedSoTheInstrumentCandidatesAreNotApplicable) {
  const RunData run = needle();
  const SamplingCheck check = check_sampling(run);
  EXPECT_TRUE(check.digitized);
  DiagnoseOptions only;
  only.only = {"spatial_ripple", "mains_interference", "stick_slip"};
  const Diagnosis d = diagnose(ForceModel::paper_interpreted(), {run}, only);
  ASSERT_EQ(d.candidates.size(), 3U);
  for (const CandidateResult& c : d.candidates) {
    EXPECT_FALSE(c.applicable)
        << c.effect;  // mains also by its own rule (sampled far below 150 Hz)
    EXPECT_FALSE(c.not_applicable.empty()) << c.effect;
  }
  const PreparedRun prepared = prepare_run(run);
  for (const std::string effect : {"spatial_ripple", "mains_interference", "stick_slip"}) {
    std::string why;
    EXPECT_FALSE(sampling_allows(effect, {&prepared}, why)) << effect;
    EXPECT_NE(why.find("digitized"), std::string::npos) << effect << ": " << why;
  }
  std::string why;
  EXPECT_TRUE(sampling_allows("stress_relaxation", {&prepared}, why))
      << "tissue effects stay candidates";
  EXPECT_TRUE(sampling_allows("shaft_friction", {&prepared}, why));
  EXPECT_TRUE(d.verdict != "spatial_ripple" && d.verdict != "mains_interference" &&
              d.verdict != "stick_slip")
      << d.verdict;
  EXPECT_TRUE(any_contains(d.warnings, "digitized")) << "the user is told why";
}

TEST(NeedleData, WarnsThatTheCorneaModelDoesNotDescribeLiver) {
  const ForceModel model = ForceModel::paper_interpreted();
  const RunData run = needle();
  const Comparison refitted = compare(model, {run}, true);
  const auto warnings = base_misfit_warnings(model, refitted);
  std::printf("needle: refitted Eq. 1 R^2 %.3f, RMSE %.4f N\n", refitted.overall.r2,
              refitted.overall.rmse_N);
  EXPECT_LT(refitted.overall.r2, kMinBaselineR2);
  EXPECT_TRUE(any_contains(warnings, "does not describe these data"))
      << "R^2 " << refitted.overall.r2;
}

TEST(SamplingCheck, ADaqWithDroppedSamplesIsNotDigitizedButAFlaggedRunIs) {
  const RunData run = test_runs::simulated_cut(0.0, 11.0);
  EXPECT_FALSE(check_sampling(run).digitized);
  RunData gappy = run;
  gappy.t_s.clear(), gappy.x_mm.clear(), gappy.force_N.clear(), gappy.channels.clear();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> keep(0.0, 1.0);
  for (std::size_t i = 0; i < run.size(); ++i) {
    if (keep(rng) > 0.4) continue;  // 60 % of the samples lost, at random
    gappy.t_s.push_back(run.t_s[i]);
    gappy.x_mm.push_back(run.x_mm[i]);
    gappy.force_N.push_back(run.force_N[i]);
  }
  EXPECT_FALSE(check_sampling(gappy).digitized) << check_sampling(gappy).why;
  RunData flagged = run;
  flagged.set("digitized", "yes");
  EXPECT_TRUE(check_sampling(flagged).digitized);
}

TEST(SimulatedCornea, RaisesNoBaseMisfitWarning) {
  const ForceModel model = ForceModel::paper_interpreted();
  const Comparison refitted = compare(
      model,
      {test_runs::simulated_cut(1.0, 12.0, 15.0, 1), test_runs::simulated_cut(1.0, 12.0, 18.0, 2)},
      true);
  std::printf("simulated cornea: refitted Eq. 1 R^2 %.4f\n", refitted.overall.r2);
  EXPECT_GT(refitted.overall.r2, kMinBaselineR2);
  const auto warnings = base_misfit_warnings(model, refitted);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
}

}  // namespace
}  // namespace rig::model
