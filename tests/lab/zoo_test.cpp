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
    for (Eigen::Index c = 0; c < width; ++c) a(static_cast<Eigen::Index>(i), c) = row[static_cast<std::size_t>(c)];
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
    const double r = residual_against(grid(0.0, 30.0, 300), [&](double t) { return forms::drift_N(s, t, 0.0); },
                                      [](double t) { return std::vector<double>{1.0, t, t * t}; });
    std::printf("sensor_drift:%-8s residual %.3f of the drift\n", form.c_str(), r);
    EXPECT_GT(r, kLeftOver) << form;
  }
}

TEST(SimulatedForms, AreNoCovariateScalingOfTheLabsExpQuadratic) {
  for (const std::string form : {"sigmoid", "hinge_all"}) {
    const EffectSlot s = slot(EffectKind::kCovariate, form);
    const double r = residual_against(grid(0.5, 3.5, 60), [&](double h) { return std::log(forms::covariate_change(s, h).cutting_factor); },
                                      [](double h) { const double z = h - 2.0; return std::vector<double>{z, z * z}; });
    std::printf("covariate:%-10s residual %.3f of the log factor\n", form.c_str(), r);
    EXPECT_GT(r, kLeftOver) << form;
  }
  const auto shift = forms::covariate_change(slot(EffectKind::kCovariate, "puncture_shift"), 3.5);
  EXPECT_EQ(shift.cutting_factor, 1.0);
  EXPECT_GT(shift.puncture_shift_mm, 0.1) << "moves the puncture: no force scaling can say that";
  // ... and levels off: not the lab's shift, quadratic in the covariate.
  const EffectSlot moving = slot(EffectKind::kCovariate, "puncture_shift");
  const double r = residual_against(grid(0.5, 3.5, 60), [&](double h) { return forms::covariate_change(moving, h).puncture_shift_mm; },
                                    [](double h) { const double z = h - 2.0; return std::vector<double>{1.0, z, z * z}; });
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
    std::printf("shaft_friction:%-16s %.4f to %.4f N/mm over 0.5-4 mm/s\n", form.c_str(), lowest, highest);
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
      return form == "dahl" ? forms::dahl_step(s, z, dx_mm) : forms::lugre_step(s, z, dx_mm, 2.0);  // 2 mm/s
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
      least = std::min(least, residual_against(back_mm, [&](double d) { return turned[static_cast<std::size_t>(std::lround(d / 0.002)) - 1]; },
                                               [&](double d) { return std::vector<double>{1.0 - 2.0 * std::min(1.0, d / grip)}; }));
    }
    std::printf("shaft_friction:%-16s residual %.3f against the lab's elastic-plastic grip\n", form.c_str(), least);
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
    if (run.x_mm[start] > 0.5 && run.t_s[i - 1] - run.t_s[start] >= 0.8) rests.push_back(run.x_mm[start]);
    start = i;
  }
  return rests;
}

void expect_stops_before_and_after_the_puncture(const model::RunData& run) {
  const auto rests = rest_depths(run);
  auto any = [&](double lo, double hi) { return std::any_of(rests.begin(), rests.end(), [&](double x) { return x > lo && x < hi; }); };
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
    const double generate_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_EQ(draw.runs.size(), 9U);
    for (const auto& expected : draw.expected) EXPECT_TRUE(legal_verdict(expected)) << expected;
    sim::expect_stops_before_and_after_the_puncture(draw.runs.front());
    if (draw.kind != DrawKind::kClean && !calibration_checked) {
      // Measured against the same eyes without the effect, the magnitude is what the label says.
      std::vector<model::RunData> clean;
      for (const auto& spec : generator.run_specs(draw.seed)) clean.push_back(sim::generate_run({}, spec));
      const double measured = effect_rms_ratio(draw.runs, clean, 0.0015);
      std::printf("draw %llu (%s): labelled %.2fx the noise (%.2fx its floor of %.1f mN), measured %.2fx the noise\n",
                  static_cast<unsigned long long>(draw.seed), draw.form.c_str(), draw.magnitude_noise, draw.magnitude,
                  1e3 * draw.floor_N, measured);
      EXPECT_NEAR(measured / draw.magnitude_noise, 1.0, 0.5);
      EXPECT_NEAR(draw.magnitude * draw.floor_N, draw.magnitude_noise * 0.0015, 1e-9);
      // The floor is the noise and the eyes' spread: well above the noise alone, eyes varying.
      EXPECT_GT(draw.floor_N, 2.0 * 0.0015);
      calibration_checked = true;
    }
    DrawScore s = score_draw(draw, 2);
    s.generate_s = generate_s;
    std::printf("draw %llu %s (%s, %.1fx): expected %s, verdict %s\n", static_cast<unsigned long long>(s.seed), s.family.c_str(),
                s.form.c_str(), s.magnitude, s.expected.front().c_str(), s.verdict.c_str());
    EXPECT_TRUE(legal_verdict(s.verdict)) << s.verdict;
    score.draws.push_back(s);
  }
  summarise(score);
  print_score(score, stdout);
  const int counted = score.catalogue_correct.total + score.catalogue_correct_below_3x.total + score.false_alarms.total +
                      score.mixtures_found.total;
  EXPECT_LE(counted, options.draws);
}

// Two effects at once are there to be found in two rounds, so each must stand above the floor
// on its own. Scaled together, one form's natural size left the other below it: in seed 200041
// (a sawtooth ripple beside Coulomb + viscous friction, 3.5x the floor together) the ripple
// alone was under half the floor, and no lab could name it. Each effect is measured here alone,
// against the same eyes without it.
TEST(BlindZoo, EachEffectOfAMixtureStandsAtTheDrawsMagnitudeOnItsOwn) {
  ZooOptions only_mixtures;
  only_mixtures.clean_share = only_mixtures.catalogue_share = only_mixtures.zoo_law_share = only_mixtures.out_of_catalogue_share = 0.0;
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
      std::printf("draw %llu %s: effect %zu (%s:%s, size %.2f) alone %.2fx the floor (labelled %.2fx); together %.2fx\n",
                  static_cast<unsigned long long>(seed), draw.form.c_str(), k, sim::effect_name(draw.hidden[k].kind).c_str(),
                  draw.hidden[k].form.c_str(), draw.hidden[k].size, measured, draw.component_magnitudes[k], draw.magnitude);
      EXPECT_GE(measured, 2.0) << "effect " << k << " of draw " << seed << " is not findable on its own";
      EXPECT_NEAR(measured / draw.component_magnitudes[k], 1.0, 0.05) << "effect " << k << " of draw " << seed;
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
TEST(BlindZoo, ACovariateActingAsAStepIsNamedWithOneRunFarPastTheOthers) { expect_verdict(70034, "covariate:temperature_C"); }

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
TEST(BlindZoo, ARippleThatGrowsWithTheLoadIsNamed) { expect_verdict(120043, "spatial_ripple"); }

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
  clean_only.catalogue_share = clean_only.zoo_law_share = clean_only.out_of_catalogue_share = clean_only.mixture_share = 0.0;
  const ZooDraw draw = ZooGenerator(clean_only).draw(20009);
  ASSERT_EQ(draw.family, "clean");
  EXPECT_EQ(score_draw(draw, 2).verdict, "none");
}

}  // namespace
}  // namespace rig::zoo

namespace rig::zoo {
namespace {

// Force at the end of each stop on the way in over its force 30 ms into the stop, per stop
// (before and after the puncture) [1]. A stop: the carriage within 20 um for 0.8 s or more.
std::vector<double> stop_relaxation_ratios(const model::RunData& run) {
  std::vector<double> ratios;
  auto mean = [&run](std::size_t from, std::size_t n) {
    double sum = 0.0;
    for (std::size_t k = from; k < from + n; ++k) sum += run.force_N[k];
    return sum / static_cast<double>(n);
  };
  std::size_t start = 0;
  for (std::size_t i = 1; i <= run.size(); ++i) {
    if (i < run.size() && std::abs(run.x_mm[i] - run.x_mm[start]) < 0.02) continue;
    const bool on_the_way_in = run.x_mm[start] > 1.5 && run.x_mm[start] < 6.0;
    if (on_the_way_in && run.t_s[i - 1] - run.t_s[start] >= 0.8 && i - start > 100) {
      ratios.push_back(mean(i - 40, 30) / mean(start + 30, 30));
    }
    start = i;
  }
  return ratios;
}

// Seed 80031 relaxes by a two-term Prony law in every stop, on 9 eyes cut at 0.6-3.5 mm/s.
// Until 2026-11-28 the few um a slow run's servo creeps forward during a stop restarted the
// simulated relaxation from t = 0 again and again: the stop after the puncture relaxed to 35 %
// of its force at 0.6 mm/s and to 64 % at 1.3 mm/s, a spread no relaxation law explains.
TEST(SimulatedRelaxation, RelaxesAStopByTheSameFractionWhateverTheCuttingSpeed) {
  const ZooDraw draw = ZooGenerator().draw(80031);
  ASSERT_EQ(draw.family, "stress_relaxation");
  std::vector<double> before, after;  // per run: the stop before and the one after the puncture
  for (const auto& run : draw.runs) {
    const auto ratios = stop_relaxation_ratios(run);
    ASSERT_EQ(ratios.size(), 2U) << run.source;
    before.push_back(ratios[0]);
    after.push_back(ratios[1]);
  }
  for (const auto* stops : {&before, &after}) {
    const auto [low, high] = std::minmax_element(stops->begin(), stops->end());
    EXPECT_LT(*high - *low, 0.12) << "relaxed to " << *low << " .. " << *high << " of the force in one stop";
    EXPECT_LT(*high, 0.9) << "the stops relax";
  }
}

// Seed 180002 slows the cut after the puncture by a random law in velocity at 8x the floor.
// Until 2026-11-28 that law could turn the tissue's force over: its slow runs cut at -0.05 N
// and dipped to -0.2 N, a tissue pulling the blade in, which no rate law of the lab (nor of
// physics) can follow. A law now weakens the tissue at most to a tenth of its force.
TEST(BlindZoo, ARandomLawInVelocityWeakensTheTissueButNeverTurnsItsForceOver) {
  const ZooDraw draw = ZooGenerator().draw(180002);
  ASSERT_EQ(draw.form, "random law in velocity, after the puncture, inserting");
  for (const auto& run : draw.runs) {
    double lowest_inside_N = 0.0;  // while the tip is inside the eye, past 1 mm
    for (std::size_t k = 0; k < run.size(); ++k) {
      if (run.x_mm[k] > 1.0) lowest_inside_N = std::min(lowest_inside_N, run.force_N[k]);
    }
    EXPECT_GT(lowest_inside_N, -0.015) << run.source << ": the measurement noise is 1.5 mN";
  }
}

// Seed 180047 puts the blade on an exponentially stiffening mount (~7 mm/N at rest). Until
// 2026-11-28 the simulator found the tip by six damped fixed-point steps, which oscillate when
// a soft mount carries a tissue whose force falls within a fraction of a mm behind the cut
// front: in 4 of 9 runs the tip ran ahead of its balance in the stop after the puncture and
// the tissue carried ~0 N from 6 to 8 mm. Now the balance is bisected: the cut stays loaded.
TEST(SimulatedMount, ASoftStiffeningMountKeepsTheCutLoadedAfterTheStop) {
  const ZooDraw draw = ZooGenerator().draw(180047);
  ASSERT_EQ(draw.form, "rig_compliance:stiffening");
  for (const auto& run : draw.runs) {
    std::size_t cutting = 0, unloaded = 0;  // samples advancing from 6 to 8 mm; those under 10 mN
    for (std::size_t k = 1; k < run.size(); ++k) {
      if (run.x_mm[k] <= 6.0 || run.x_mm[k] >= 8.0 || run.x_mm[k] <= run.x_mm[k - 1] + 5e-4) continue;
      ++cutting;
      if (std::abs(run.force_N[k]) < 0.01) ++unloaded;
    }
    ASSERT_GT(cutting, 100U) << run.source;
    EXPECT_LT(unloaded, cutting / 20) << run.source << ": " << unloaded << " of " << cutting << " samples cut at ~0 N";
  }
}

// The share of a run's tearing that a sawtooth of the simulator's own law leaves unexplained
// [1]: the force on new depth inside the cut (0.3 mm past the detected puncture to 0.2 mm
// before the cut's end), less a quadratic in depth, fitted by 8 harmonics of depth over the
// simulator's own period (forms::tearing_cycles_per_mm) at the run's commanded speed v.
double tearing_left_by_its_own_law(const model::RunData& data) {
  const model::PreparedRun run = model::prepare_run(data);
  const double period_mm = 1.0 / sim::forms::tearing_cycles_per_mm(run.velocity_cmd_mm_s);  // the simulator's own law
  std::vector<std::size_t> rows;
  double deepest = -1e9;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const double x = data.x_mm[i];
    if (x > deepest + 1e-4 && x > run.seg.x_pi_mm + 0.3 && x < run.seg.x_c_mm - 0.2) rows.push_back(i);
    deepest = std::max(deepest, x);
  }
  constexpr int kHarmonics = 8;
  Eigen::MatrixXd design(static_cast<Eigen::Index>(rows.size()), 3 + 2 * kHarmonics);
  Eigen::VectorXd force(design.rows());
  for (Eigen::Index r = 0; r < design.rows(); ++r) {
    const double x = data.x_mm[rows[static_cast<std::size_t>(r)]] - run.seg.x_pi_mm;
    design(r, 0) = 1.0, design(r, 1) = x, design(r, 2) = x * x;
    for (int k = 1; k <= kHarmonics; ++k) {
      design(r, 1 + 2 * k) = std::sin(2.0 * std::numbers::pi * k * x / period_mm);
      design(r, 2 + 2 * k) = std::cos(2.0 * std::numbers::pi * k * x / period_mm);
    }
    force(r) = data.force_N[rows[static_cast<std::size_t>(r)]];
  }
  const auto left = [&](Eigen::Index columns) {
    const Eigen::MatrixXd x = design.leftCols(columns);
    return (force - x * x.colPivHouseholderQr().solve(force)).squaredNorm();
  };
  return left(design.cols()) / left(3);
}

// Force samples in the hold at the deepest point (the carriage within 30 um of it, 0.1 s
// from either end): their median [N] and how many stray more than 20 mN from it.
struct DeepestHold {
  double median_N = NAN;
  int strays = 0;
};

DeepestHold deepest_hold(const model::RunData& run) {
  const double deepest_mm = *std::max_element(run.x_mm.begin(), run.x_mm.end());
  std::vector<double> held;
  for (std::size_t i = 0; i < run.size(); ++i) {
    if (std::abs(run.x_mm[i] - deepest_mm) < 0.03) held.push_back(run.force_N[i]);
  }
  DeepestHold hold;
  if (held.size() < 400) return hold;  // under 0.4 s at 1 kHz: no hold
  held = std::vector<double>(held.begin() + 100, held.end() - 100);
  std::vector<double> sorted = held;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  hold.median_N = sorted[sorted.size() / 2];
  for (const double f : held) hold.strays += std::abs(f - hold.median_N) > 0.02 ? 1 : 0;
  return hold;
}

// Tissue grips a blade that stops: the friction stays loaded through the hold at the deepest
// point. Until 2026-11-28 the simulated Stribeck friction took its sign from the motor's
// velocity, tanh(v / 0.02 mm/s), so at rest it vanished and the servo's few-um dither flipped
// it, in single samples, by up to +-65 mN. It is now LuGre's bristle state.
TEST(SimulatedFriction, StribeckFrictionStaysLoadedThroughTheHoldAndIgnoresTheServosDither) {
  const ZooDraw draw = ZooGenerator().draw(120056);
  ASSERT_EQ(draw.form, "shaft_friction:stribeck");
  for (const auto& run : draw.runs) {
    const DeepestHold hold = deepest_hold(run);
    ASSERT_FALSE(std::isnan(hold.median_N)) << run.source << ": no hold at the deepest point";
    // The cut is through at 12 mm: without friction the hold reads about 0 N.
    EXPECT_GT(hold.median_N, 0.02) << run.source;
    EXPECT_EQ(hold.strays, 0) << run.source;
  }
}

// Seed 120056: Stribeck friction (LuGre, 3.7x the floor). With the friction held at rest and
// flipped at once on retraction the best form explained 62 % of the excess and the verdict was
// `unexplained`; a grip that reverses over a length (here 0.076 mm) explains 81 %.
TEST(BlindZoo, FrictionThatTurnsOverAGripLengthIsNamed) { expect_verdict(120056, "shaft_friction"); }

// Seed 120047 tears in build-and-release steps whose length follows the cutting speed. Until
// 2026-11-28 the simulator recomputed the pattern as sawtooth(depth / period(speed now)): the
// servo's speed ripple of a few percent then moved the tenth tear by a tenth of a period, a
// jitter no tearing has and no term can fit. The tears now add up over the cut.
TEST(SimulatedTearing, KeepsTheLengthOfItsTearsAlongTheCutWhateverTheServoRipple) {
  const ZooDraw draw = ZooGenerator().draw(120047);
  ASSERT_EQ(draw.family, "stick_slip");
  ASSERT_NE(draw.form.find("velocity_weakening"), std::string::npos) << draw.form;
  std::vector<double> left;  // per run
  for (const auto& run : draw.runs) {
    left.push_back(tearing_left_by_its_own_law(run));
  }
  std::sort(left.begin(), left.end());
  // Before: 0.12-0.29 of the tearing left, median 0.19; after: 0.07-0.21, median 0.09 (both
  // measured with the earlier period law, 0.35 (v/2)^0.3 mm).
  EXPECT_LT(left[left.size() / 2], 0.14) << "median share left; the largest " << left.back();
}

// The largest step between successive 20 ms means of the force in any stop inside the cut of
// the run [N], 1 kHz samples; -1 if the run has no such stop. A stop: the carriage within 20 um
// for 0.8 s or more, 3-6.5 mm deep.
double largest_step_in_a_stop(const model::RunData& run) {
  double largest = -1.0;
  std::size_t start = 0;
  for (std::size_t i = 1; i <= run.size(); ++i) {
    if (i < run.size() && std::abs(run.x_mm[i] - run.x_mm[start]) < 0.02) continue;
    if (run.x_mm[start] > 3.0 && run.x_mm[start] < 6.5 && run.t_s[i - 1] - run.t_s[start] >= 0.8) {
      largest = std::max(largest, 0.0);
      double previous = NAN;
      for (std::size_t k = start + 100; k + 120 < i; k += 20) {  // 0.1 s from either end: the blade at rest
        double mean = 0.0;
        for (std::size_t j = k; j < k + 20; ++j) mean += run.force_N[j] / 20.0;
        if (!std::isnan(previous)) largest = std::max(largest, std::abs(mean - previous));
        previous = mean;
      }
    }
    start = i;
  }
  return largest;
}

// A blade held inside the cut keeps the tear it has built up. Until 2026-11-28 the simulated
// tearing let go as soon as the servo settled 1 um back during a stop: the force stepped by
// the tearing's amplitude in the middle of a hold.
TEST(SimulatedTearing, HoldsItsTearWhileTheBladeIsStopped) {
  const ZooDraw draw = ZooGenerator().draw(120047);
  ASSERT_EQ(draw.family, "stick_slip");
  for (const auto& run : draw.runs) {
    // Before: steps of 34-43 mN in the slow runs' stops; after: at most 7.5 mN (noise 1.5 mN).
    const double step_N = largest_step_in_a_stop(run);
    EXPECT_GE(step_N, 0.0) << run.source << ": no stop in the cut (the protocol stops at 5.5 mm)";
    EXPECT_LT(step_N, 0.01) << run.source;
  }
}

// Seed 120047 tears in build-and-release steps whose period grows with the cutting speed
// (0.24 mm at 0.5 mm/s, 0.41 mm at 3.6 mm/s) at 3.4x its floor. With one period in mm for
// every run, locked to the population's puncture, the tearing term gained at most 0.9 % and
// `iop_stiffness` ranked first (2026-11-28, seeds 120000-120059). The family's third form
// (period as a power law of the speed, each eye its own amplitude and phase) found the law;
// since 2026-12-07 the fourth (each tear read off where the force lets go, so any period law
// is followed) wins by BIC 390 and gains 56 %. Either is a form that follows the speed; a
// single period in mm for every run is not.
TEST(BlindZoo, TearingWhosePeriodFollowsTheCuttingSpeedIsRankedFirstWithAFormThatFollowsIt) {
  const ZooDraw draw = ZooGenerator().draw(120047);
  ASSERT_EQ(draw.family, "stick_slip");
  model::DiagnoseOptions options;
  options.threads = 2;
  const model::Diagnosis d = model::diagnose(model::ForceModel::paper_interpreted(), draw.runs, options);
  ASSERT_FALSE(d.candidates.empty());
  const model::CandidateResult& first = d.candidates.front();
  EXPECT_EQ(first.effect, "stick_slip");
  EXPECT_TRUE(first.significant);
  const bool follows_the_speed = first.evidence.find("period follows the cutting speed") != std::string::npos ||
                                 first.evidence.find("read off the force's releases") != std::string::npos;
  EXPECT_TRUE(follows_the_speed) << first.evidence;
  EXPECT_GT(first.gain_pct, 15.0);
  EXPECT_TRUE(d.verdict == "stick_slip" || (d.verdict == "unexplained" && d.partial_candidate == "stick_slip")) << d.verdict;
}

}  // namespace
}  // namespace rig::zoo
