// The control loop closed around the simulated rig, on a virtual clock.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "simulated_rig.hpp"

namespace rig {
namespace {

using rt::CommandKind;
using rt::CommandResult;
using rt::RunState;

bool in_state(sim::SimulatedRig& rig, RunState state, double timeout_s) {
  return rig.run_until([state](const rt::StatusSnapshot& st) { return st.state == state; },
                       timeout_s);
}

TEST(ClosedLoop, HomingFindsTheHomeSwitchAndParksTheCarriage) {
  sim::SimulatedRig rig;
  ASSERT_EQ(rig.command(CommandKind::kHome), CommandResult::kAccepted);
  ASSERT_TRUE(in_state(rig, RunState::kReady, 30.0));
  const rt::StatusSnapshot st = rig.status();
  EXPECT_TRUE(st.homed);
  EXPECT_NEAR(st.position_mm, 18.0, 0.05);
  EXPECT_NEAR(rig.physics().truth().carriage_mm, 18.0, 0.05);
}

TEST(ClosedLoop, ARunIsRefusedBeforeHomingAndBeforeTaring) {
  sim::SimulatedRig rig;
  EXPECT_EQ(rig.command(CommandKind::kArm, rt::RunParams{}), CommandResult::kWrongState);
  rig.command(CommandKind::kHome);
  ASSERT_TRUE(in_state(rig, RunState::kReady, 30.0));
  EXPECT_EQ(rig.command(CommandKind::kArm, rt::RunParams{}), CommandResult::kNotTared);
}

TEST(ClosedLoop, ACutHoldsTwoMillimetresPerSecondAndPeaksWhereTheTissuePunctures) {
  sim::SimulatedRig rig;
  rt::RunParams params;
  params.iop_mmHg = 15.0;
  params.velocity_mm_s = 2.0;
  params.depth_mm = 14.0;
  const sim::RecordedRun run = rig.record_run(params);
  ASSERT_EQ(run.final_status.state, RunState::kDone);
  ASSERT_GT(run.samples.size(), 5000U);
  const double surface = rig.physics().params().tissue.surface_mm;
  // Mean velocity over the insertion, away from its ends.
  const rt::Sample* first = nullptr;
  const rt::Sample* last = nullptr;
  const rt::Sample* peak = &run.samples.front();
  for (const auto& s : run.samples) {
    if (s.phase != rt::CutPhase::kInsert) continue;
    const double depth = s.position_mm - surface;
    if (depth > 0.5 && first == nullptr) first = &s;
    if (depth < 13.5) last = &s;
    if (depth < 6.0 && s.force_N > peak->force_N) peak = &s;
  }
  ASSERT_NE(first, nullptr);
  ASSERT_NE(last, nullptr);
  const double velocity = (last->position_mm - first->position_mm) / (last->t_s - first->t_s);
  EXPECT_NEAR(velocity, 2.0, 0.02);
  const double x_pi = rig.physics().tissue().puncture_depth_mm(15.0);
  EXPECT_NEAR(peak->position_mm - surface, x_pi, 0.1);
  EXPECT_GT(peak->force_N, 0.15);
  EXPECT_LT(peak->force_N, 0.40);
}

// A busy machine holds the loop off the CPU for 10-17 ms now and then (measured on a 2-core
// CI VM under load). The DAQ keeps driving the motor through such a gap (its watchdog is
// longer), so the reference must follow the whole gap: capped at 10 periods, the cut came
// out 1-3 % slow.
TEST(ClosedLoop, ACutKeepsItsVelocityThroughStallsShorterThanTheDaqWatchdog) {
  const sim::PhysicsParams physics;
  rt::LoopSettings settings = sim::loop_settings_for(physics);
  settings.daq_watchdog_ms = 15.0;  // the simulated rig's config
  sim::SimulatedRig rig(physics, {}, settings);
  rig.physics().set_watchdog_ms(15);
  rig.command(CommandKind::kHome);
  ASSERT_TRUE(in_state(rig, RunState::kReady, 60.0));
  rig.command(CommandKind::kTare);
  ASSERT_TRUE(rig.run_until([](const rt::StatusSnapshot& st) { return st.tared; }, 5.0));
  std::vector<rt::Sample> samples;
  std::vector<rt::Event> events;
  rig.drain(samples, events);
  samples.clear();
  rt::RunParams params;
  params.run_id = 1;
  params.velocity_mm_s = 2.0;
  params.depth_mm = 10.0;
  ASSERT_EQ(rig.command(CommandKind::kArm, params), CommandResult::kAccepted);
  int stalls = 0;
  for (int cycle = 0; cycle < 60000 && rig.status().state != RunState::kDone &&
                      rig.status().state != RunState::kFault;
       ++cycle) {
    if (cycle % 40 == 0 && rig.status().state == RunState::kCutting) {
      rig.clock().add_wakeup_delay(13'000'000);  // [ns] held off the CPU for 13 ms
      ++stalls;
    }
    rig.loop().run_for(rig.loop().period_ns());
    rig.drain(samples, events);
  }
  ASSERT_EQ(rig.status().state, RunState::kDone) << rt::to_string(rig.status().fault);
  ASSERT_GT(stalls, 50);
  const double surface = rig.physics().params().tissue.surface_mm;
  const rt::Sample* first = nullptr;
  const rt::Sample* last = nullptr;
  for (const auto& s : samples) {
    if (s.phase != rt::CutPhase::kInsert) continue;
    const double depth = s.position_mm - surface;
    if (depth > 0.5 && first == nullptr) first = &s;
    if (depth < 9.5) last = &s;
  }
  ASSERT_NE(first, nullptr);
  ASSERT_NE(last, nullptr);
  const double velocity =
      (last->position_mm - first->position_mm) / (last->t_s - first->t_s);  // [mm/s]
  EXPECT_NEAR(velocity, 2.0, 0.02);
}

TEST(ClosedLoop, TwoCommandsTakenInOneCycleAreEachAnsweredInTheStatus) {
  sim::SimulatedRig rig;
  rt::Command tare;
  tare.kind = CommandKind::kTare;
  tare.id = 501;
  rt::Command home;
  home.kind = CommandKind::kHome;
  home.id = 502;
  ASSERT_TRUE(rig.channels().commands.push(tare));  // two clients, same cycle
  ASSERT_TRUE(rig.channels().commands.push(home));
  rig.loop().run_for(rig.loop().period_ns());
  const rt::StatusSnapshot st = rig.status();
  EXPECT_EQ(st.last_command_id, 502U);
  ASSERT_TRUE(st.answer_to(501).has_value())
      << "the first client's answer was lost: it would wait for a 504";
  EXPECT_EQ(*st.answer_to(501), CommandResult::kAccepted);
  ASSERT_TRUE(st.answer_to(502).has_value());
  EXPECT_EQ(*st.answer_to(502), CommandResult::kAccepted);
  EXPECT_FALSE(st.answer_to(503).has_value());
}

}  // namespace
}  // namespace rig
