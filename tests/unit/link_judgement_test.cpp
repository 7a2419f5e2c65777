// The DAQ link is judged by time without a valid reply, counted over the cycles in which rigd
// itself asked on time: a real silence is caught after safety.link_lost_after_ms, a cycle that
// rigd woke late for is rigd's own lateness (counted apart), and a loop late again and again
// cannot hide a dead link past four times as many failed requests as the limit holds periods.
// Virtual clock, whole loop.
#include <gtest/gtest.h>
#include <cmath>

#include "simulated_rig.hpp"

namespace rig {
namespace {

using drivers::IoStatus;
using rt::CommandKind;
using rt::FaultCode;
using rt::RunState;

constexpr double kLinkLostAfter_ms = 4.0;
constexpr std::int64_t kLateWake_ns = 700'000;  // more than half a 1 ms period

class LinkJudgement : public ::testing::Test {
 protected:
  void SetUp() override {
    rig_.command(CommandKind::kHome);
    ASSERT_TRUE(rig_.run_until(
        [](const rt::StatusSnapshot& s) { return s.state == RunState::kReady; }, 60));
    rig_.command(CommandKind::kTare);
    ASSERT_TRUE(rig_.run_until([](const rt::StatusSnapshot& s) { return s.tared; }, 5));
    rt::RunParams params;
    params.run_id = 7;
    ASSERT_EQ(rig_.command(CommandKind::kArm, params), rt::CommandResult::kAccepted);
    const double surface = rig_.physics().params().tissue.surface_mm;
    ASSERT_TRUE(rig_.run_until(
        [surface](const rt::StatusSnapshot& s) { return s.position_mm > surface + 2.0; }, 30));
  }

  static rt::LoopSettings settings() {
    rt::LoopSettings loop = sim::loop_settings_for(sim::PhysicsParams{});
    loop.safety.link_lost_after_ms = kLinkLostAfter_ms;
    return loop;
  }

  // One cycle, `late_ns` after its deadline.
  void cycle(std::int64_t late_ns = 0) {
    rig_.clock().add_wakeup_delay(late_ns);
    rig_.loop().run_for(rig_.loop().period_ns());
  }

  sim::SimulatedRig rig_{sim::PhysicsParams{}, {}, settings()};
};

TEST_F(LinkJudgement, ASilentDaqFaultsTheRunOnceNoValidReplyCameForTheConfiguredTimeAndNotBefore) {
  rig_.daq().inject(IoStatus::kTimeout);
  for (int i = 0; i < 3; ++i) cycle();
  EXPECT_EQ(rig_.status().state, RunState::kCutting) << "3 ms of silence is not yet 4 ms";
  cycle();
  cycle();
  const rt::StatusSnapshot st = rig_.status();
  EXPECT_EQ(st.state, RunState::kFault);
  EXPECT_EQ(st.fault, FaultCode::kLinkLost);
  EXPECT_GE(st.fault_value, kLinkLostAfter_ms);
  EXPECT_LE(st.fault_value, kLinkLostAfter_ms + 1.0) << "detected within a period of the limit";
}

TEST_F(LinkJudgement, FailedReadsInCyclesRigdWokeLateForAreCountedApartAndDoNotFaultTheRun) {
  rig_.daq().inject(IoStatus::kTimeout);
  for (int i = 0; i < 8; ++i)
    cycle(kLateWake_ns);  // 8 late cycles: twice the limit, below four times
  rig_.daq().inject(IoStatus::kOk);
  rig_.advance(0.01);
  EXPECT_EQ(rig_.status().state, RunState::kCutting) << "rigd's own lateness is not a lost link";
  EXPECT_GE(rig_.channels().counters.late_wake_misses.load(), 8U);
  EXPECT_GE(rig_.channels().counters.late_wakes.load(), 8U);
}

TEST_F(LinkJudgement, ASilentDaqWhoseReadsRunToTheirTimeoutStillFaultsTheRunAtTheLimit) {
  rig_.daq().inject(IoStatus::kTimeout);
  rig_.daq().take_per_read(rig_.clock(), 700'000);  // the response timeout of config/rigd.sim.toml
  int cycles = 0;
  while (rig_.status().state != RunState::kFault && cycles < 100) {
    cycle();
    ++cycles;
  }
  const rt::StatusSnapshot st = rig_.status();
  EXPECT_EQ(st.fault, FaultCode::kLinkLost);
  EXPECT_GE(st.fault_value, kLinkLostAfter_ms);
  EXPECT_LE(st.fault_value, kLinkLostAfter_ms + 1.0) << "detected within a period of the limit";
}

TEST_F(LinkJudgement,
       ALoopLateAgainAndAgainStillFaultsADeadLinkAfterFourTimesAsManyFailedRequests) {
  rig_.daq().inject(IoStatus::kLinkDown);
  int cycles = 0;
  while (rig_.status().state != RunState::kFault && cycles < 100) {
    cycle(kLateWake_ns);
    ++cycles;
  }
  const rt::StatusSnapshot st = rig_.status();
  EXPECT_EQ(st.fault, FaultCode::kLinkLost);
  EXPECT_EQ(cycles, 16) << "4 x 4 ms at 1 kHz";
  EXPECT_GE(st.fault_value, 4.0 * kLinkLostAfter_ms);
  EXPECT_LE(st.fault_value, 4.0 * kLinkLostAfter_ms + 2.0)
      << "late cycles still come about 1 ms apart";
}

TEST(LinkAtRest, ATareOrAHomingAskedWhileAReplyIsMissingIsTakenButNotWhileTheDaqIsSilent) {
  rt::LoopSettings loop = sim::loop_settings_for(sim::PhysicsParams{});
  loop.safety.link_lost_after_ms = 10.0;
  sim::SimulatedRig rig{sim::PhysicsParams{}, {}, loop};
  rig.command(CommandKind::kHome);
  ASSERT_TRUE(
      rig.run_until([](const rt::StatusSnapshot& s) { return s.state == RunState::kReady; }, 60));
  rig.daq().inject(IoStatus::kTimeout);  // replies lost while the tare is asked
  rig.advance(0.003);
  EXPECT_EQ(rig.command(CommandKind::kTare), rt::CommandResult::kAccepted)
      << "a tare does not move the carriage";
  rig.daq().inject(IoStatus::kOk);
  ASSERT_TRUE(rig.run_until([](const rt::StatusSnapshot& s) { return s.tared; }, 5));
  rig.advance(0.01);  // the offset applies from the cycle after the tare ends
  EXPECT_EQ(rig.status().state, RunState::kReady);
  EXPECT_LT(std::abs(rig.status().force_N), 0.01)
      << "the tare took the resting load cell's reading [N]";
  // Homing moves the carriage: a lone reply lost is no reason to refuse it, a silent DAQ is.
  rig.daq().inject(IoStatus::kTimeout);
  rig.advance(0.001);
  rig.daq().inject(IoStatus::kOk);
  rig.advance(0.001);
  rig.daq().inject(IoStatus::kTimeout);
  EXPECT_EQ(rig.command(CommandKind::kHome), rt::CommandResult::kAccepted) << "one reply missing";
  rig.advance(0.005);
  ASSERT_EQ(rig.status().state, RunState::kHoming);
  rig.daq().inject(IoStatus::kOk);
  rig.command(CommandKind::kStop);
  ASSERT_TRUE(
      rig.run_until([](const rt::StatusSnapshot& s) { return s.state != RunState::kHoming; }, 5));
  rig.daq().inject(IoStatus::kTimeout);
  rig.advance(0.003);
  EXPECT_EQ(rig.command(CommandKind::kHome), rt::CommandResult::kLinkDown)
      << "three replies in a row missing";
}

}  // namespace
}  // namespace rig
