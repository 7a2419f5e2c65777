// The simulated physics behind the blind zoo's draws: relaxation, mounts, Stribeck friction and
// tearing behave as their physics does (per stop, per speed, under the servo's ripple), so a
// miss in the zoo is the lab's and not the simulator's. Part of test_lab_zoo (label lab).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "diagnosis.hpp"
#include "prepared_run.hpp"
#include "rig/sim/effect_forms.hpp"
#include "zoo_scorer.hpp"

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
    EXPECT_LT(*high - *low, 0.12) << "relaxed to " << *low << " .. " << *high
                                  << " of the force in one stop";
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
      if (run.x_mm[k] <= 6.0 || run.x_mm[k] >= 8.0 || run.x_mm[k] <= run.x_mm[k - 1] + 5e-4)
        continue;
      ++cutting;
      if (std::abs(run.force_N[k]) < 0.01) ++unloaded;
    }
    ASSERT_GT(cutting, 100U) << run.source;
    EXPECT_LT(unloaded, cutting / 20)
        << run.source << ": " << unloaded << " of " << cutting << " samples cut at ~0 N";
  }
}

// The share of a run's tearing that a sawtooth of the simulator's own law leaves unexplained
// [1]: the force on new depth inside the cut (0.3 mm past the detected puncture to 0.2 mm
// before the cut's end), less a quadratic in depth, fitted by 8 harmonics of depth over the
// simulator's own period (forms::tearing_cycles_per_mm) at the run's commanded speed v.
double tearing_left_by_its_own_law(const model::RunData& data) {
  const model::PreparedRun run = model::prepare_run(data);
  const double period_mm =
      1.0 / sim::forms::tearing_cycles_per_mm(run.velocity_cmd_mm_s);  // the simulator's own law
  std::vector<std::size_t> rows;
  double deepest = -1e9;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const double x = data.x_mm[i];
    if (x > deepest + 1e-4 && x > run.seg.x_pi_mm + 0.3 && x < run.seg.x_c_mm - 0.2)
      rows.push_back(i);
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
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2),
                   sorted.end());
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
      for (std::size_t k = start + 100; k + 120 < i;
           k += 20) {  // 0.1 s from either end: the blade at rest
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
  const model::Diagnosis d =
      model::diagnose(model::ForceModel::paper_interpreted(), draw.runs, options);
  ASSERT_FALSE(d.candidates.empty());
  const model::CandidateResult& first = d.candidates.front();
  EXPECT_EQ(first.effect, "stick_slip");
  EXPECT_TRUE(first.significant);
  const bool follows_the_speed =
      first.evidence.find("period follows the cutting speed") != std::string::npos ||
      first.evidence.find("read off the force's releases") != std::string::npos;
  EXPECT_TRUE(follows_the_speed) << first.evidence;
  EXPECT_GT(first.gain_pct, 15.0);
  EXPECT_TRUE(d.verdict == "stick_slip" ||
              (d.verdict == "unexplained" && d.partial_candidate == "stick_slip"))
      << d.verdict;
}

}  // namespace
}  // namespace rig::zoo
