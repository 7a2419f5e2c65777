// The load cell's offset-step detector (level_shifts.hpp) on synthetic runs: jumps of the
// tissue it must leave alone, and sensor steps it must still find. 500 Hz, 1.5 mN white
// noise, as on the zoo's runs.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "level_shifts.hpp"

namespace rig::model {
namespace {

constexpr double kRate_Hz = 500.0;
constexpr double kNoise_N = 0.0015;

// A run of `duration_s`: the carriage at position(t) [mm], the force force(t, x) [N] plus noise.
RunData synthetic_run(double duration_s, const std::function<double(double)>& position,
                      const std::function<double(double, double)>& force) {
  RunData run;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, kNoise_N);
  for (double t = 0.0; t < duration_s; t += 1.0 / kRate_Hz) {
    const double x = position(t);
    run.t_s.push_back(t);
    run.x_mm.push_back(x);
    run.force_N.push_back(force(t, x) + noise(rng));
  }
  return run;
}

// A logistic step of `size` [N] at `at` [s], 5 ms wide (the zoo's sensor step).
double step(double t, double at, double size) {
  return size / (1.0 + std::exp(-(t - at) / 0.005));
}

// At the end of the cut a soft mount snaps the tip through: the unloading force falls to
// 64 mN, then to nothing at once, and stays there while the carriage goes on (draw 220035:
// 13 "offset steps" in 9 runs, every one of them this).
TEST(OffsetSteps, ADropOntoTheContactFreeLevelIsTheBladeLetGoNotASensorStep) {
  const auto x = [](double t) { return -2.0 + 1.0 * t; };  // 1 mm/s
  const RunData run = synthetic_run(14.0, x, [](double, double xm) {
    if (xm < 8.0) return std::max(0.0, 0.02 * xm);
    return xm < 9.0 ? 0.16 - 0.1 * (xm - 8.0) : 0.0;
  });
  EXPECT_TRUE(find_offset_steps(run, kNoise_N).empty());
}

// A law in velocity that weakens the tissue while the blade moves gives its force back the
// moment the carriage stops: a jump up as the motion changes (draw 130011, +23 mN).
TEST(OffsetSteps, AJumpAsTheCarriageStopsIsTheTissuesRateLawNotASensorStep) {
  const auto x = [](double t) { return std::min(-2.0 + 0.7 * t, 5.5); };  // stops at t = 10.71 s
  const RunData run = synthetic_run(13.0, x, [](double t, double xm) {
    const bool moving = -2.0 + 0.7 * t < 5.5;
    return std::max(0.0, 0.03 * xm) * (moving ? 0.86 : 1.0);
  });
  EXPECT_TRUE(find_offset_steps(run, kNoise_N).empty());
}

// Rising at 0.08 N/mm, then a jump up onto a flat plateau: the stiffness changes across it,
// which a sensor step never does (draw 130030, +39 mN at the puncture of a rate law).
TEST(OffsetSteps, AJumpUpThatChangesTheStiffnessIsTheTissuesNotASensorStep) {
  const auto x = [](double t) { return -2.0 + 1.5 * t; };
  const RunData run = synthetic_run(8.0, x, [](double, double xm) {
    if (xm < 0.0) return 0.0;
    return xm < 3.8 ? 0.05 * xm : 0.22;  // 0.19 N, then 0.22 N flat
  });
  EXPECT_TRUE(find_offset_steps(run, kNoise_N).empty());
}

// A stop on the way in, then the carriage sets off again and the load comes back in a jump
// within half a millimetre (a soft mount taken up: draw 220035, run 8, +38 mN).
TEST(OffsetSteps, AJumpJustAfterTheCarriageSetsOffIsTheTissueReloadingNotASensorStep) {
  const auto x = [](double t) {
    return t < 4.0 ? -2.0 + 1.875 * t : (t < 5.0 ? 5.5 : 5.5 + 3.6 * (t - 5.0));
  };
  const RunData run = synthetic_run(6.5, x, [](double t, double xm) {
    const double base = std::max(0.0, 0.035 * std::min(xm, 5.5));  // 0.19 N at the stop
    return base + step(t, 5.12, 0.038);  // 0.43 mm after the carriage set off
  });
  EXPECT_TRUE(find_offset_steps(run, kNoise_N).empty());
}

// At 0.63 mm/s a 0.15 s window holds 0.09 mm of travel, and a puncture's loss of stiffness on
// a soft mount (0.043 N/mm before, flat after) drowned in the slopes' errors: the puncture was
// taken for a sensor step (draw 290008, run 0, -63 mN).
TEST(OffsetSteps, ASlowPunctureOnASoftMountIsNoSensorStep) {
  const auto x = [](double t) { return -2.0 + 0.63 * t; };
  const RunData run = synthetic_run(16.0, x, [](double, double xm) {
    if (xm < 0.0) return 0.0;
    return xm < 4.6 ? 0.052 * xm : 0.18;  // 0.24 N at the puncture, then the cutting plateau
  });
  EXPECT_TRUE(find_offset_steps(run, kNoise_N).empty());
}

// A cut that ends at rest: the lines at the run's last samples are read from the sums up to
// its end (the sums were one entry short, and a line ending there read past them).
TEST(OffsetSteps, ARunEndingAtRestHasNoStepAtItsEnd) {
  const auto x = [](double t) { return std::min(-2.0 + 2.0 * t, 12.0); };
  const RunData run =
      synthetic_run(9.0, x, [](double, double xm) { return std::max(0.0, 0.02 * xm); });
  EXPECT_TRUE(find_offset_steps(run, kNoise_N).empty());
}

// The same motions with a sensor step instead: each is still found, at its time and size.
TEST(OffsetSteps, SensorStepsWhileTheBladeAdvancesAreStillFoundUpAndDown) {
  struct Case {
    double speed_mm_s, at_s, size_N;
  };
  for (const Case c : {Case{1.5, 4.0, +0.030}, Case{1.5, 4.0, -0.030}, Case{0.63, 8.0, -0.040},
                       Case{0.63, 8.0, +0.025}}) {
    const auto x = [&](double t) { return -2.0 + c.speed_mm_s * t; };
    const RunData run = synthetic_run(12.0, x, [&](double t, double xm) {
      return std::max(0.0, 0.02 * xm) + step(t, c.at_s, c.size_N);
    });
    const std::vector<OffsetStep> steps = find_offset_steps(run, kNoise_N);
    ASSERT_EQ(steps.size(), 1U) << c.speed_mm_s << " mm/s, " << c.size_N << " N";
    EXPECT_NEAR(steps[0].t_s, c.at_s, 0.01);
    EXPECT_NEAR(steps[0].size_N, c.size_N, 0.1 * std::abs(c.size_N));
  }
}

}  // namespace
}  // namespace rig::model
