// User terms are first-class: a term offered as a candidate (a term file) is scored by
// diagnose, added by fit, its fitted values reported and saved in the model file; a term
// already in the model is never added twice; covariates and phase indicators reach the
// expression; term files and the CLI's `explain` -> `fit --add user:NAME` path work.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>

#include "command.hpp"
#include "diagnosis.hpp"
#include "effects/user_expression.hpp"
#include "injected_effects.hpp"
#include "lab_scenarios.hpp"
#include "model_fit.hpp"
#include "run_csv.hpp"
#include "test_paths.hpp"

namespace rig::model {
namespace {

constexpr double kSquare_N_per_mm2 = 2e-4;

// Three runs with a force k x^2 while retracting: small enough for a quick fit.
const std::vector<RunData>& dragged_runs() {
  static const std::vector<RunData> runs = [] {
    std::vector<RunData> all = testing::mechanism_runs({}, 11);
    std::vector<RunData> three = {all[0], all[4], all[8]};
    testing::add_retraction_square(three, kSquare_N_per_mm2);
    return three;
  }();
  return runs;
}

UserTerm drag_back() {
  return {"drag_back", "k*x^2", "retraction", {{"k", 0.0}}};
}

int count(const std::vector<std::string>& names, const std::string& name) {
  return static_cast<int>(std::count(names.begin(), names.end(), name));
}

TEST(UserTerms, ACandidateTermIsScoredByDiagnoseAndNamedWhenItExplainsTheResidual) {
  ForceModel model = ForceModel::paper_interpreted();
  model.candidate_terms.push_back(drag_back());
  DiagnoseOptions o;
  o.only = {"user:drag_back", "shaft_friction"};
  const Diagnosis d = diagnose(model, dragged_runs(), o);
  ASSERT_EQ(d.candidates.size(), 2U);
  EXPECT_EQ(d.candidates.front().effect, "user:drag_back") << d.candidates.front().evidence;
  EXPECT_TRUE(d.candidates.front().significant);
  EXPECT_EQ(d.verdict, "user:drag_back");
}

TEST(UserTerms, DiagnoseDoesNotOfferATermTheModelAlreadyHas) {
  ForceModel model = ForceModel::paper_interpreted();
  model.user_terms.push_back(drag_back());
  model.candidate_terms.push_back(drag_back());
  DiagnoseOptions o;
  o.only = {"user:drag_back", "sensor_drift"};
  const Diagnosis d = diagnose(model, dragged_runs(), o);
  EXPECT_EQ(count(d.base_effects, "user:drag_back"), 1);
  ASSERT_EQ(d.candidates.size(), 1U);
  EXPECT_EQ(d.candidates.front().effect, "sensor_drift");
}

TEST(UserTerms, FitAddsACandidateTermAndSavesItsFittedValues) {
  ForceModel model = ForceModel::paper_interpreted();
  model.candidate_terms.push_back(drag_back());
  const FitReport f = fit_model(model, dragged_runs(), {"user:drag_back"});
  EXPECT_EQ(count(f.effects, "user:drag_back"), 1);
  ASSERT_TRUE(f.params.count("user:drag_back"));
  EXPECT_NEAR(f.params.at("user:drag_back").at("k"), kSquare_N_per_mm2, 0.1 * kSquare_N_per_mm2);
  EXPECT_LT(f.after_cv_rmse_N, 1.25 * f.noise_floor_N);
  testing::ScratchDir dir("user-term-fit");
  f.fitted.save(dir.file("fitted.toml"));
  const ForceModel back = ForceModel::load(dir.file("fitted.toml"));
  ASSERT_EQ(back.user_terms.size(), 1U);
  EXPECT_EQ(back.user_terms[0].expression, "k*x^2");
  EXPECT_EQ(back.user_terms[0].phase, "retraction");
  EXPECT_DOUBLE_EQ(back.user_terms[0].params.at("k"), f.params.at("user:drag_back").at("k"));
  EXPECT_TRUE(back.candidate_terms.empty());
}

TEST(UserTerms, FitNeverAddsATermTwice) {
  ForceModel model = ForceModel::paper_interpreted();
  model.user_terms.push_back(drag_back());
  model.candidate_terms.push_back(drag_back());
  const std::vector<RunData> runs = {dragged_runs()[0], dragged_runs()[1]};
  const FitReport f = fit_model(model, runs, {"user:drag_back", "sensor_drift", "sensor_drift"});
  EXPECT_EQ(count(f.effects, "user:drag_back"), 1);
  EXPECT_EQ(count(f.effects, "sensor_drift"), 1);
  EXPECT_EQ(f.fitted.user_terms.size(), 1U);
  bool said_already = false, said_twice = false;
  for (const auto& w : f.warnings) {
    said_already =
        said_already || w.find("user:drag_back is already in the model") != std::string::npos;
    said_twice = said_twice || w.find("sensor_drift was asked for twice") != std::string::npos;
  }
  EXPECT_TRUE(said_already);
  EXPECT_TRUE(said_twice);
}

TEST(UserTerms, ReadRunCovariatesAndPhaseIndicators) {
  RunData data = dragged_runs()[0];
  data.set("blade_uses", "3");
  const PreparedRun run = prepare_run(data);
  const effects::UserExpression term(
      {"wear", "k*blade_uses*x*is_retraction + is_hold", "all", {{"k", 0.5}}});
  EXPECT_EQ(term.covariates(), std::vector<std::string>{"blade_uses"});
  SampleView s{&run, 10, 2.0, 1.0, 0.0, -1.0, 0.0, 0.0, Phase::kRetraction};
  const double k = 0.5;
  EXPECT_DOUBLE_EQ(term.add(s, &k, 0.0), 0.5 * 3.0 * 2.0);
  s.phase = Phase::kCutting;
  EXPECT_DOUBLE_EQ(term.add(s, &k, 0.0), 0.0);
  s.phase = Phase::kHold;
  EXPECT_DOUBLE_EQ(term.add(s, &k, 0.0), 1.0);
}

TEST(UserTerms, AnUnknownNameMakesTheTermInapplicableAndFitSaysWhich) {
  const PreparedRun run = prepare_run(dragged_runs()[0]);
  const effects::UserExpression term({"typo", "k*blade_use*x", "all", {{"k", 0.0}}});
  std::string why_not;
  EXPECT_FALSE(term.applicable({&run}, why_not));
  EXPECT_NE(why_not.find("'blade_use'"), std::string::npos) << why_not;
  ForceModel model = ForceModel::paper_interpreted();
  model.candidate_terms.push_back({"typo", "k*blade_use*x", "all", {{"k", 0.0}}});
  try {
    fit_model(model, {dragged_runs()[0]}, {"user:typo"});
    FAIL() << "fit with an unknown variable";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("user:typo"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("blade_use"), std::string::npos) << e.what();
  }
}

TEST(UserTerms, AParameterNamedLikeAVariableIsAnError) {
  EXPECT_THROW(effects::UserExpression({"bad", "x*2", "all", {{"x", 1.0}}}), ModelFileError);
  EXPECT_THROW(effects::UserExpression({"bad", "k*x", "sideways", {{"k", 1.0}}}), ModelFileError);
}

TEST(TermFiles, RoundTripAndBadFilesNameTheFileLineAndKey) {
  testing::ScratchDir dir("term-files");
  save_user_terms(dir.file("t.toml"),
                  {drag_back(), {"wear", "c1*(blade_uses-4)*x", "insertion", {{"c1", 2e-4}}}});
  const std::vector<UserTerm> back = load_user_terms(dir.file("t.toml"));
  ASSERT_EQ(back.size(), 2U);
  EXPECT_EQ(back[1].name, "wear");
  EXPECT_EQ(back[1].expression, "c1*(blade_uses-4)*x");
  EXPECT_DOUBLE_EQ(back[1].params.at("c1"), 2e-4);
  std::ofstream(dir.file("bad.toml"))
      << "[terms.a]\nexpression = \"k*x\"\n\n[model]\nname = \"m\"\n";
  try {
    load_user_terms(dir.file("bad.toml"));
    FAIL() << "a term file with a [model] section";
  } catch (const ModelFileError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.file("bad.toml") + ":4"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("'model'"), std::string::npos) << e.what();
  }
  std::ofstream(dir.file("empty.toml")) << "[terms.a]\nphase = \"hold\"\n";
  EXPECT_THROW(load_user_terms(dir.file("empty.toml")), ModelFileError);
}

std::string rig(const std::string& args) {
  return testing::run_command(testing::bin("rig") + " " + args, false).output;
}

TEST(Cli, ExplainProposesATermThatFitAddsFromTheTermFile) {
  testing::ScratchDir dir("cli-explain");
  std::filesystem::create_directories(dir.file("runs"));
  for (std::size_t r = 0; r < dragged_runs().size(); ++r)
    write_run_csv(dragged_runs()[r], dir.file("runs/run" + std::to_string(r) + ".csv"));
  const auto e = nlohmann::json::parse(rig("--format json model explain " + dir.file("runs") +
                                           " --save-term " + dir.file("t.toml")));
  ASSERT_TRUE(e["proposed"].get<bool>()) << e.dump(2);
  EXPECT_EQ(e["term"]["name"], "explained");
  EXPECT_EQ(e["features"][0]["feature"], "x^2");
  EXPECT_EQ(e["features"][0]["gate"], "retraction");
  ASSERT_TRUE(std::ifstream(dir.file("t.toml")).good());
  const std::string fit = "--format json model fit " + dir.file("runs") + " --terms " +
                          dir.file("t.toml") + " --add user:explained";
  const auto f = nlohmann::json::parse(rig(fit + " --save " + dir.file("m.toml")));
  EXPECT_EQ(f["effects"], nlohmann::json::array({"user:explained"}));
  EXPECT_TRUE(f["params"]["user:explained"].contains("c1"));
  EXPECT_LT(f["after"]["cv_rmse_N"].get<double>(), 0.5 * f["before"]["cv_rmse_N"].get<double>());
  const auto again = nlohmann::json::parse(rig(fit + " --model " + dir.file("m.toml")));
  EXPECT_EQ(again["effects"], nlohmann::json::array({"user:explained"}));
  ASSERT_FALSE(again["warnings"].empty());
  EXPECT_NE(again["warnings"].back().get<std::string>().find("already in the model"),
            std::string::npos);
}

}  // namespace
}  // namespace rig::model
