// The explainer (model/lab/explainer): on runs with an effect outside the catalogue it
// proposes a term made of the right features that brings the CV error to the noise floor;
// on effect-free runs it proposes nothing. Nine simulated runs per dataset, seconds each.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <random>

#include "injected_effects.hpp"
#include "lab_scenarios.hpp"
#include "lasso_path.hpp"
#include "model_fit.hpp"
#include "residual_explainer.hpp"

namespace rig::model::explainer {
namespace {

const std::vector<RunData>& clean_runs() {
  static const std::vector<RunData> runs = testing::mechanism_runs({}, 7);
  return runs;
}

Explanation explain_timed(const std::vector<RunData>& runs, const char* what,
                          const ExplainOptions& o = {}) {
  const auto start = std::chrono::steady_clock::now();
  Explanation e = explain(ForceModel::paper_interpreted(), runs, o);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "%s: %s\n  where %s; baseline %.4f N, floor %.4f N, predicted %.4f N, after %.4f N; %.1f s\n",
      what, e.summary.c_str(), e.where.c_str(), e.baseline_cv_rmse_N, e.noise_floor_N,
      e.predicted_cv_rmse_N, e.after_cv_rmse_N, seconds);
  return e;
}

bool selected(const Explanation& e, const std::string& expression, const std::string& gate) {
  for (const ExplainedFeature& f : e.features) {
    if (f.expression == expression && (gate.empty() || f.gate == gate)) return true;
  }
  return false;
}

// Six groups of 400 rows, 11 standard normal columns, y = sum weight_j x_j + 0.2 N(0, 1).
LassoPath synthetic_path(const std::vector<std::pair<int, double>>& weights) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<GramStats> groups;
  std::vector<int> fold_of;
  for (int g = 0; g < 6; ++g) {
    Eigen::MatrixXd x(400, 11);
    for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = normal(rng);
    Eigen::VectorXd y(400);
    for (Eigen::Index i = 0; i < y.size(); ++i) {
      y(i) = 0.2 * normal(rng);
      for (const auto& [column, weight] : weights) y(i) += weight * x(i, column);
    }
    groups.push_back({x.transpose() * x, x.transpose() * y, y.squaredNorm(), 400.0});
    fold_of.push_back(g % 3);
  }
  return LassoPath(groups, fold_of, 4);
}

TEST(LassoPath, PruningDropsAFeatureThatCarriesAlmostNothingAndKeepsOneThatCarriesMuch) {
  const LassoPath faint = synthetic_path({{7, 0.5}, {3, 0.01}});
  EXPECT_EQ(faint.prune(faint.with_support({3, 7}), 0.05).support, std::vector<int>{7});
  const LassoPath strong = synthetic_path({{7, 0.5}, {2, 0.3}});
  EXPECT_EQ(strong.prune(strong.with_support({2, 7}), 0.05).support, (std::vector<int>{2, 7}));
}

TEST(LassoPath, SelectsTheOneColumnThatCarriesTheSignalAmongTenNoiseColumns) {
  const LassoPath path = synthetic_path({{7, 0.5}});
  const int step = path.choose();
  ASSERT_GE(step, 0);
  const PathStep& chosen = path.steps()[static_cast<std::size_t>(step)];
  ASSERT_EQ(chosen.support, std::vector<int>{7});
  EXPECT_NEAR(chosen.coefficients(0), 0.5, 0.02);
  EXPECT_NEAR(chosen.cv_sse / path.empty_sse(), 0.04 / 0.29, 0.02);  // noise 0.2^2 of 0.5^2 + 0.2^2
}

TEST(Explainer, NamesASquareLawThatActsOnlyDuringRetraction) {
  std::vector<RunData> runs = clean_runs();
  testing::add_retraction_square(runs, 2e-4);
  const Explanation e = explain_timed(runs, "retraction x^2");
  ASSERT_TRUE(e.proposed) << e.summary;
  EXPECT_TRUE(selected(e, "x^2", "retraction")) << e.where;
  EXPECT_EQ(e.features.front().gate, "retraction") << e.where;
  EXPECT_LT(e.after_cv_rmse_N, e.noise_floor_N + 0.25 * (e.baseline_cv_rmse_N - e.noise_floor_N));
}

TEST(Explainer, NamesBladeWearAsACovariateTimesDepth) {
  std::vector<RunData> runs = clean_runs();
  testing::add_blade_wear(runs, 2e-4);
  const Explanation e = explain_timed(runs, "blade_uses x depth");
  ASSERT_TRUE(e.proposed) << e.summary;
  // blade_uses runs 0..8 over the session (mean 4): the wear feature, centred, while inserting.
  EXPECT_TRUE(selected(e, "(blade_uses-4)*x", "insertion")) << e.where;
  EXPECT_EQ(e.features.front().expression, "(blade_uses-4)*x") << e.where;
  EXPECT_LT(e.after_cv_rmse_N, e.noise_floor_N + 0.25 * (e.baseline_cv_rmse_N - e.noise_floor_N));
}

TEST(Explainer, WorksOnASingleRunWithChunksOfItAsFolds) {
  std::vector<RunData> runs = {clean_runs()[4]};
  testing::add_retraction_square(runs, 2e-4);
  const Explanation e = explain_timed(runs, "one run, retraction x^2");
  ASSERT_TRUE(e.proposed) << e.summary;
  EXPECT_TRUE(selected(e, "x^2", "retraction")) << e.where;
}

TEST(Explainer, ProposesNothingOnEffectFreeRuns) {
  const Explanation e = explain_timed(clean_runs(), "effect-free");
  EXPECT_FALSE(e.proposed) << e.summary;
}

}  // namespace
}  // namespace rig::model::explainer
