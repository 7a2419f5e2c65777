// A covariate term's range: how far past the values it was fitted on it predicts, and the
// model file that keeps it (effects/covariate_range.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "effect_catalogue.hpp"
#include "effects/covariate_scaling.hpp"
#include "model_family.hpp"
#include "prepared_run.hpp"
#include "run_generator.hpp"

namespace rig::model {
namespace {

RunData one_run() {
  sim::GeneratorOptions g;
  g.physics.tissue.eye_variability = 0.0;
  sim::RunSpec spec;
  spec.depth_mm = 12.0;
  spec.eye_id = "unit";
  return sim::generate_run(g, spec);
}

// The blind zoo's failures this answers: a covariate acting as a step, the held-out run the
// only one far past the others, was extrapolated as a slope to 5x its force (70034, 2026-11-28);
// held exactly to the edge, wear steepest at the last blade use lost its end (300026).
TEST(CovariateTerms, ExtrapolateACountOneStepAndAMeasuredValueNotAtAllAndAModelFileKeepsThat) {
  std::vector<RunData> data;
  for (const char* uses : {"1", "2", "3", "5"}) {
    data.push_back(one_run());
    data.back().meta.emplace_back("blade_uses", uses);
  }
  std::vector<PreparedRun> prepared;
  for (const RunData& r : data) prepared.push_back(prepare_run(r));
  const ForceModel paper = ForceModel::paper_interpreted();
  const std::vector<const PreparedRun*> fitted_on = {&prepared[0], &prepared[1]};  // 1 and 2 uses
  EffectCatalogue catalogue(paper, fitted_on);
  catalogue.set_form_selection(false);  // the family below takes the default form, unfitted
  const auto term = catalogue.make_form("covariate:blade_uses", "exponential, all phases");
  const double c = 0.8;  // exp(c z), z in spreads of the fitted runs
  auto scale_at = [&](const EffectTerm& t, std::size_t run) {
    const SampleView s{&prepared[run], 0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, Phase::kApproach};
    return t.scale(s, &c);
  };
  EXPECT_GT(scale_at(*term, 1), scale_at(*term, 0));         // inside the range: the slope
  EXPECT_NEAR(scale_at(*term, 1), std::exp(c), 1e-9);        // mean 1.5, spread 0.5: z = 1 at 2
  EXPECT_NEAR(scale_at(*term, 2), std::exp(3.0 * c), 1e-9);  // 3 uses: one step past, taken
  EXPECT_NEAR(scale_at(*term, 3), std::exp(3.0 * c), 1e-9);  // 5 uses: held to 3, one step
  const std::string words = term->evidence(EvidenceInput{&c, fitted_on, {}});
  EXPECT_NE(words.find("held to 1..2, the values fitted on, and 1 past them"), std::string::npos)
      << words;
  // A measured value (hours post mortem, not whole numbers) is held to the values fitted on.
  const std::vector<const PreparedRun*> measured = {&prepared[0], &prepared[2]};
  for (const std::size_t k : {0U, 2U}) {
    auto& meta = data[k].meta;
    meta.erase(std::remove_if(meta.begin(), meta.end(),
                              [](const auto& kv) { return kv.first == "post_mortem_h"; }),
               meta.end());
    meta.emplace_back("post_mortem_h", k == 0 ? "1.5" : "2.5");
    prepared[k] = prepare_run(data[k]);
  }
  EffectCatalogue hours(paper, measured);
  hours.set_form_selection(false);
  const auto held = hours.make_form("covariate:post_mortem_h", "exponential, all phases");
  const auto* held_cov = dynamic_cast<const effects::CovariateScaling*>(held.get());
  ASSERT_NE(held_cov, nullptr);
  EXPECT_DOUBLE_EQ(held_cov->range().reach, 0.0);
  EXPECT_DOUBLE_EQ(held_cov->range().high, 2.5);
  // The model file keeps the range and the reach; a file from before the reach holds to the
  // edge; a hand-edited file with a range the term cannot hold to is an error naming it.
  const ModelFamily family(paper, catalogue, {"covariate:blade_uses"});
  const auto settings = family.settings(family.predictor().initial_params());
  ASSERT_EQ(settings.size(), 1U);
  EXPECT_DOUBLE_EQ(settings[0].params.at("low"), 1.0);
  EXPECT_DOUBLE_EQ(settings[0].params.at("high"), 2.0);
  EXPECT_DOUBLE_EQ(settings[0].params.at("reach"), 1.0);
  const auto reloaded = catalogue.make_saved(settings[0]);
  const auto* cov = dynamic_cast<const effects::CovariateScaling*>(reloaded.get());
  ASSERT_NE(cov, nullptr);
  EXPECT_DOUBLE_EQ(cov->range().high, 2.0);
  EXPECT_DOUBLE_EQ(cov->range().reach, 1.0);
  EffectSetting older = settings[0];
  older.params.erase("reach");
  const auto reloaded_older = catalogue.make_saved(older);
  const auto* older_cov = dynamic_cast<const effects::CovariateScaling*>(reloaded_older.get());
  ASSERT_NE(older_cov, nullptr);
  EXPECT_DOUBLE_EQ(older_cov->range().reach, 0.0);
  EffectSetting negative = settings[0];
  negative.params["reach"] = -1.0;
  EXPECT_THROW((void)catalogue.make_saved(negative), std::invalid_argument);
  EffectSetting inverted = settings[0];
  inverted.params["low"] = 3.0;  // above high
  try {
    (void)catalogue.make_saved(inverted);
    ADD_FAILURE() << "an inverted range was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("covariate:blade_uses"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("low <= high"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rig::model
