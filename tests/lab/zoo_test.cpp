// The simulator is not the model lab's mirror, and the effect zoo is fit for blind scoring:
// every hidden-effect form leaves a residual against the best fit of the lab's own term,
// eyes differ by default, every protocol stops before and after the puncture, and a small
// blind zoo (seeds never used while developing) is generated, labelled and scored. The
// lab's rates are printed, not asserted: the lab changes under this test (docs/model-lab.md).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <set>

#include "diagnosis.hpp"
#include "effect_catalogue.hpp"
#include "lab_scenarios.hpp"
#include "prepared_run.hpp"
#include "rig/sim/effect_forms.hpp"
#include "rig/sim/rig_physics.hpp"
#include "zoo_scorer.hpp"

namespace rig::sim {
namespace {

EffectSlot slot(EffectKind kind, const std::string& form) {
  const auto forms = effect_forms(kind);
  EffectSlot s;
  s.on = true;
  s.form = static_cast<int>(std::find(forms.begin(), forms.end(), form) - forms.begin());
  return s;
}

// RMS of the least-squares residual of y on the columns, relative to the RMS of y.
double relative_residual(const Eigen::MatrixXd& columns, const Eigen::VectorXd& y) {
  const Eigen::VectorXd beta = columns.colPivHouseholderQr().solve(y);
  return (y - columns * beta).norm() / std::max(y.norm(), 1e-300);
}

// Fits y(x) by the lab's linear-in-parameters shape (columns from x) and returns the residual.
double residual_against(const std::vector<double>& xs, const std::function<double(double)>& y,
                        const std::function<std::vector<double>(double)>& lab_columns) {
  const auto width = static_cast<Eigen::Index>(lab_columns(xs.front()).size());
  Eigen::MatrixXd a(static_cast<Eigen::Index>(xs.size()), width);
  Eigen::VectorXd b(static_cast<Eigen::Index>(xs.size()));
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const auto row = lab_columns(xs[i]);
    for (Eigen::Index c = 0; c < width; ++c)
      a(static_cast<Eigen::Index>(i), c) = row[static_cast<std::size_t>(c)];
    b(static_cast<Eigen::Index>(i)) = y(xs[i]);
  }
  return relative_residual(a, b);
}

std::vector<double> grid(double from, double to, int n) {
  std::vector<double> out;
  for (int i = 0; i < n; ++i) out.push_back(from + (to - from) * i / (n - 1));
  return out;
}

// Half a per cent of the effect is far more than any rounding of an exact special case.
constexpr double kLeftOver = 0.005;

// Every simulated law against every lab form of its family: sim_forms_test.cpp.

TEST(SimulatedForms, AreNoDriftOfTheLabsQuadraticInTime) {
  for (const std::string form : {"thermal", "step", "warmup"}) {
    EffectSlot s = slot(EffectKind::kSensorDrift, form);
    s.run_values[0] = 0.1;  // thermal time constant 3.8 s
    s.run_values[1] = 0.4;  // step at 9.8 s
    const double r = residual_against(
        grid(0.0, 30.0, 300), [&](double t) { return forms::drift_N(s, t, 0.0); },
        [](double t) {
          return std::vector<double>{1.0, t, t * t};
        });
    std::printf("sensor_drift:%-8s residual %.3f of the drift\n", form.c_str(), r);
    EXPECT_GT(r, kLeftOver) << form;
  }
}

TEST(SimulatedForms, AreNoCovariateScalingOfTheLabsExpQuadratic) {
  for (const std::string form : {"sigmoid", "hinge_all"}) {
    const EffectSlot s = slot(EffectKind::kCovariate, form);
    const double r = residual_against(
        grid(0.5, 3.5, 60),
        [&](double h) { return std::log(forms::covariate_change(s, h).cutting_factor); },
        [](double h) {
          const double z = h - 2.0;
          return std::vector<double>{z, z * z};
        });
    std::printf("covariate:%-10s residual %.3f of the log factor\n", form.c_str(), r);
    EXPECT_GT(r, kLeftOver) << form;
  }
  const auto shift = forms::covariate_change(slot(EffectKind::kCovariate, "puncture_shift"), 3.5);
  EXPECT_EQ(shift.cutting_factor, 1.0);
  EXPECT_GT(shift.puncture_shift_mm, 0.1) << "moves the puncture: no force scaling can say that";
  // ... and levels off: not the lab's shift, quadratic in the covariate.
  const EffectSlot moving = slot(EffectKind::kCovariate, "puncture_shift");
  const double r = residual_against(
      grid(0.5, 3.5, 60),
      [&](double h) { return forms::covariate_change(moving, h).puncture_shift_mm; },
      [](double h) {
        const double z = h - 2.0;
        return std::vector<double>{1.0, z, z * z};
      });
  std::printf("covariate:puncture_shift residual %.3f against the lab's quadratic shift\n", r);
  EXPECT_GT(r, kLeftOver);
}

TEST(SimulatedForms, FrictionDependsOnSpeedOrHoldsAtRestUnlikeTheLabsTerm) {
  // The lab's friction is the same at every speed and zero in a hold.
  for (const std::string form : {"coulomb_viscous", "stribeck"}) {
    const EffectSlot s = slot(EffectKind::kShaftFriction, form);
    double lowest = 1e9, highest = 0.0;
    for (const double v : grid(0.5, 4.0, 36)) {
      lowest = std::min(lowest, forms::friction_per_mm(s, v));
      highest = std::max(highest, forms::friction_per_mm(s, v));
    }
    std::printf("shaft_friction:%-16s %.4f to %.4f N/mm over 0.5-4 mm/s\n", form.c_str(), lowest,
                highest);
    EXPECT_GT((highest - lowest) / highest, 0.2) << form;
  }
  const EffectSlot dahl = slot(EffectKind::kShaftFriction, "dahl");
  double z = 0.0;
  for (int i = 0; i < 1000; ++i) z += forms::dahl_step(dahl, z, 0.002);  // 2 mm inward
  const double at_rest = z + forms::dahl_step(dahl, z, 0.0);
  EXPECT_GT(at_rest, 0.005) << "Dahl friction keeps its value while the blade rests";
}

// The lab's presliding friction reverses along a straight ramp over its grip length (an
// elastic-plastic grip); Dahl's and LuGre's states turn exponentially, whatever the length.
TEST(SimulatedForms, FrictionReversesUnlikeTheLabsElasticPlasticGrip) {
  for (const std::string form : {"dahl", "stribeck"}) {
    const EffectSlot s = slot(EffectKind::kShaftFriction, form);
    const auto step = [&](double z, double dx_mm) {
      return form == "dahl" ? forms::dahl_step(s, z, dx_mm)
                            : forms::lugre_step(s, z, dx_mm, 2.0);  // 2 mm/s
    };
    double z = 0.0;
    for (int i = 0; i < 1000; ++i) z += step(z, 0.002);  // 2 mm inward
    std::vector<double> back_mm, turned;
    for (int i = 1; i <= 500; ++i) {  // 1 mm back
      z += step(z, -0.002);
      back_mm.push_back(0.002 * i);
      turned.push_back(z);
    }
    double least = 1e9;
    for (const double grip : grid(0.005, 1.0, 400)) {
      least = std::min(
          least,
          residual_against(
              back_mm,
              [&](double d) {
                return turned[static_cast<std::size_t>(std::lround(d / 0.002)) - 1];
              },
              [&](double d) { return std::vector<double>{1.0 - 2.0 * std::min(1.0, d / grip)}; }));
    }
    std::printf("shaft_friction:%-16s residual %.3f against the lab's elastic-plastic grip\n",
                form.c_str(), least);
    EXPECT_GT(least, kLeftOver) << form;
  }
}

TEST(SimulatedEyes, DifferByDefaultAndAreIdenticalWhenVariationIsOff) {
  PhysicsParams params;
  RigPhysics varied(params);
  std::set<double> stiffness, puncture;
  for (int eye = 0; eye < 8; ++eye) {
    varied.mount_new_eye(2.0);
    stiffness.insert(varied.tissue().eye_stiffness());
    puncture.insert(varied.tissue().puncture_depth_mm(15.0));
  }
  EXPECT_EQ(stiffness.size(), 8U);
  EXPECT_GT(*puncture.rbegin() - *puncture.begin(), 0.05);
  params.tissue.eye_variability = 0.0;
  RigPhysics identical(params);
  identical.mount_new_eye(2.0);
  EXPECT_EQ(identical.tissue().eye_stiffness(), 1.0);
  EXPECT_EQ(identical.tissue().puncture_depth_mm(15.0), 3.55);
}

// Depths [mm] where the blade rested for at least 0.8 s inside the eye.
std::vector<double> rest_depths(const model::RunData& run) {
  std::vector<double> rests;
  std::size_t start = 0;
  for (std::size_t i = 1; i <= run.size(); ++i) {
    if (i < run.size() && std::abs(run.x_mm[i] - run.x_mm[start]) < 0.02) continue;
    if (run.x_mm[start] > 0.5 && run.t_s[i - 1] - run.t_s[start] >= 0.8)
      rests.push_back(run.x_mm[start]);
    start = i;
  }
  return rests;
}

void expect_stops_before_and_after_the_puncture(const model::RunData& run) {
  const auto rests = rest_depths(run);
  auto any = [&](double lo, double hi) {
    return std::any_of(rests.begin(), rests.end(), [&](double x) { return x > lo && x < hi; });
  };
  EXPECT_TRUE(any(1.5, 3.0)) << run.source << ": no stop before the puncture";
  EXPECT_TRUE(any(5.0, 6.0)) << run.source << ": no stop after the puncture";
  EXPECT_TRUE(any(11.5, 12.5)) << run.source << ": no hold at depth";
}

TEST(EveryScenario, StopsBeforeAndAfterThePunctureWhateverTheHiddenEffect) {
  for (const std::string hidden : {"rate_dependence", "stress_relaxation"}) {
    const auto runs = testing::scenario_runs({hidden}, 5);
    expect_stops_before_and_after_the_puncture(runs.front());
    expect_stops_before_and_after_the_puncture(runs.back());
  }
}

}  // namespace
}  // namespace rig::sim

namespace rig::zoo {
namespace {

bool legal_verdict(const std::string& v) {
  if (v == "none" || v == "unexplained" || v.rfind("covariate:", 0) == 0) return true;
  const auto& names = model::EffectCatalogue::builtin_names();
  return std::find(names.begin(), names.end(), v) != names.end();
}

// Seeds 770001... were never used while the simulator and the zoo were written.
TEST(BlindZoo, DrawsAreLabelledCalibratedAndScored) {
  const ZooGenerator generator;
  ScoreOptions options;
  options.first_seed = 770001;
  options.draws = 3;
  ZooScore score;
  bool calibration_checked = false;
  for (int k = 0; k < options.draws; ++k) {
    const auto start = std::chrono::steady_clock::now();
    const ZooDraw draw = generator.draw(options.first_seed + static_cast<std::uint64_t>(k));
    const double generate_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_EQ(draw.runs.size(), 9U);
    for (const auto& expected : draw.expected) EXPECT_TRUE(legal_verdict(expected)) << expected;
    sim::expect_stops_before_and_after_the_puncture(draw.runs.front());
    if (draw.kind != DrawKind::kClean && !calibration_checked) {
      // Measured against the same eyes without the effect, the magnitude is what the label says.
      std::vector<model::RunData> clean;
      for (const auto& spec : generator.run_specs(draw.seed))
        clean.push_back(sim::generate_run({}, spec));
      const double measured = effect_rms_ratio(draw.runs, clean, 0.0015);
      std::printf(
          "draw %llu (%s): labelled %.2fx the noise (%.2fx its floor of %.1f mN), measured %.2fx "
          "the noise\n",
          static_cast<unsigned long long>(draw.seed), draw.form.c_str(), draw.magnitude_noise,
          draw.magnitude, 1e3 * draw.floor_N, measured);
      EXPECT_NEAR(measured / draw.magnitude_noise, 1.0, 0.5);
      EXPECT_NEAR(draw.magnitude * draw.floor_N, draw.magnitude_noise * 0.0015, 1e-9);
      // The floor is the noise and the eyes' spread: well above the noise alone, eyes varying.
      EXPECT_GT(draw.floor_N, 2.0 * 0.0015);
      calibration_checked = true;
    }
    DrawScore s = score_draw(draw, 2);
    s.generate_s = generate_s;
    std::printf("draw %llu %s (%s, %.1fx): expected %s, verdict %s\n",
                static_cast<unsigned long long>(s.seed), s.family.c_str(), s.form.c_str(),
                s.magnitude, s.expected.front().c_str(), s.verdict.c_str());
    EXPECT_TRUE(legal_verdict(s.verdict)) << s.verdict;
    score.draws.push_back(s);
  }
  summarise(score);
  print_score(score, stdout);
  const int counted = score.catalogue_correct.total + score.catalogue_correct_below_3x.total +
                      score.false_alarms.total + score.mixtures_found.total;
  EXPECT_LE(counted, options.draws);
}

// Two effects at once are there to be found in two rounds, so each must stand above the floor
// on its own. Scaled together, one form's natural size left the other below it: in seed 200041
// (a sawtooth ripple beside Coulomb + viscous friction, 3.5x the floor together) the ripple
// alone was under half the floor, and no lab could name it. Each effect is measured here alone,
// against the same eyes without it.
TEST(BlindZoo, EachEffectOfAMixtureStandsAtTheDrawsMagnitudeOnItsOwn) {
  ZooOptions only_mixtures;
  only_mixtures.clean_share = only_mixtures.catalogue_share = only_mixtures.zoo_law_share =
      only_mixtures.out_of_catalogue_share = 0.0;
  const ZooGenerator generator(only_mixtures);
  // 770102 hides a relaxation spectrum whose strength saturates: it cannot reach 3x, and its
  // label says what it reaches.
  for (const std::uint64_t seed : {200041ULL, 770102ULL}) {
    const ZooDraw draw = generator.draw(seed);
    ASSERT_EQ(draw.kind, DrawKind::kMixture);
    ASSERT_EQ(draw.hidden.size(), 2U);
    ASSERT_EQ(draw.component_magnitudes.size(), 2U);
    const std::vector<sim::RunSpec> specs = generator.run_specs(seed);
    std::vector<model::RunData> clean;
    for (const auto& spec : specs) clean.push_back(sim::generate_run({}, spec));
    for (std::size_t k = 0; k < 2; ++k) {
      sim::GeneratorOptions alone;
      alone.effects = {draw.hidden[k]};
      std::vector<model::RunData> runs;
      for (const auto& spec : specs) runs.push_back(sim::generate_run(alone, spec));
      const double measured = effect_rms_ratio(runs, clean, draw.floor_N);  // x the true floor
      std::printf(
          "draw %llu %s: effect %zu (%s:%s, size %.2f) alone %.2fx the floor (labelled %.2fx); "
          "together %.2fx\n",
          static_cast<unsigned long long>(seed), draw.form.c_str(), k,
          sim::effect_name(draw.hidden[k].kind).c_str(), draw.hidden[k].form.c_str(),
          draw.hidden[k].size, measured, draw.component_magnitudes[k], draw.magnitude);
      EXPECT_GE(measured, 2.0) << "effect " << k << " of draw " << seed
                               << " is not findable on its own";
      EXPECT_NEAR(measured / draw.component_magnitudes[k], 1.0, 0.05)
          << "effect " << k << " of draw " << seed;
    }
  }
}

}  // namespace
}  // namespace rig::zoo

namespace rig::zoo {
namespace {

// Regressions from the development range (not scoring draws): the draw, scored as the bench
// scores it, gets the verdict it should.
void expect_verdict(std::uint64_t seed, const std::string& verdict) {
  const ZooDraw draw = ZooGenerator().draw(seed);
  ASSERT_EQ(draw.family, verdict);
  ASSERT_GE(draw.magnitude, 3.0);
  EXPECT_EQ(score_draw(draw, 2).verdict, verdict) << "draw " << seed << ": " << draw.form;
}

// Seed 70034 is a step link of temperature acting everywhere, 3.5x its floor, and one run at
// 25 C far past the other eight (19.8-23.0 C). Its fold extrapolated the covariate's slope to
// that run and made the population error 5x worse, so `diagnose` said "none" until covariate
// terms were held to the values they were fitted on (2026-11-28).
TEST(BlindZoo, ACovariateActingAsAStepIsNamedWithOneRunFarPastTheOthers) {
  expect_verdict(70034, "covariate:temperature_C");
}

// Seed 70046 is a temperature step acting everywhere at 7.4x its floor. `iop_stiffness` gains
// 68.9 % within eyes and makes unseen eyes 1.5 % worse; the temperature covariate gains 68.7 %
// on unseen eyes and 57.6 % within them. Ranked by the larger gain alone, the first was the
// verdict (2026-11-28).
TEST(BlindZoo, ACandidateThatPredictsUnseenEyesWorseLosesATieToOneThatImprovesBothChannels) {
  expect_verdict(70046, "covariate:temperature_C");
}

// Seed 120043 is a lead-screw ripple whose amplitude follows the thread load, 0.3 + F/0.2 N,
// at 5x its floor. With the ripple's amplitude one number per run the best form gained 40.6 %
// and left too much of the excess: `unexplained` (2026-11-28, seeds 120000-120059). The
// family's third form, a sine proportional to the measured force, names it.
TEST(BlindZoo, ARippleThatGrowsWithTheLoadIsNamed) {
  expect_verdict(120043, "spatial_ripple");
}

// Seed 200038 (a scored draw: it missed in the range 200000-200059, whose figure stands as
// measured) is a bent link of post_mortem_h after the puncture, 3.4x its floor. The
// covariate's per-phase form fits two slopes on the cutting scale from nine eyes; the eyes'
// spread left after it was estimated as if nothing had been fitted, at 6/9 of the truth: a
// floor of 5.5 mN (true 7.6), so 30.6 % of the excess stood above it (bar 30 %) and the
// verdict was `unexplained` until the spread counted those slopes (2026-11-29).
TEST(BlindZoo, ACovariatesSlopesFittedOnNineEyesDoNotLowerTheFloorTheyAreJudgedAgainst) {
  expect_verdict(200038, "covariate:post_mortem_h");
}

// Seed 220031 (scored in the range 220000-220059): one of its runs pushes the force past the
// rig's 2 N limit, and the interlock stops it, as on a real rig. The bench aborted there (an
// uncaught exception after 31 draws, 2026-11-29); the draw now stands outside every rate,
// counted with its reason, and the range goes on.
TEST(BlindZoo, ADrawWhoseRunTheRigsInterlockStopsIsCountedApartAndTheRangeGoesOn) {
  ScoreOptions one;
  one.first_seed = 220031;
  one.draws = 1;
  const ZooScore z = score_zoo(ZooGenerator(), one);
  ASSERT_EQ(z.not_run.size(), 1U);
  EXPECT_TRUE(z.draws.empty());
  EXPECT_NE(z.not_run[0].why.find("force limit"), std::string::npos) << z.not_run[0].why;
  EXPECT_NE(z.not_run[0].why.find("ZOO-220031-"), std::string::npos) << "names the run";
  std::FILE* sink = std::tmpfile();
  ASSERT_NE(sink, nullptr);
  print_score(z, sink);  // the table says so
  std::rewind(sink);
  std::string table(4096, '\0');
  table.resize(std::fread(table.data(), 1, table.size(), sink));
  std::fclose(sink);
  EXPECT_NE(table.find("1 draw(s) not run"), std::string::npos) << table;
}

// Seed 20009 of the effect-free tuning draws: 9 eyes, no effect. `covariate:blade_uses`
// ("after the puncture only") fits the eyes' random cutting scales to the run order and gains
// 27.3 % on unseen eyes; against the 16 % bar of every candidate it was the verdict until the
// covariate bar (30 % at 9 runs, 2026-11-28).
TEST(BlindZoo, EyesThatDifferByChanceAreNotTakenForACovariate) {
  ZooOptions clean_only;
  clean_only.catalogue_share = clean_only.zoo_law_share = clean_only.out_of_catalogue_share =
      clean_only.mixture_share = 0.0;
  const ZooDraw draw = ZooGenerator(clean_only).draw(20009);
  ASSERT_EQ(draw.family, "clean");
  EXPECT_EQ(score_draw(draw, 2).verdict, "none");
}

// Seed 120056: Stribeck friction (LuGre, 3.7x the floor). With the friction held at rest and
// flipped at once on retraction the best form explained 62 % of the excess and the verdict was
// `unexplained`; a grip that reverses over a length (here 0.076 mm) explains 81 %.
TEST(BlindZoo, FrictionThatTurnsOverAGripLengthIsNamed) {
  expect_verdict(120056, "shaft_friction");
}

}  // namespace
}  // namespace rig::zoo
