// Output writes that the DAQ does not take while it answers reads: lost or garbled answers
// fault the run after safety.max_failed_writes in a row, an explicit refusal in the next
// cycle whatever the setting (docs/faults.md). Virtual clock, whole loop.
#include <gtest/gtest.h>

#include "recorder.hpp"
#include "simulated_rig.hpp"
#include "timing_fault.hpp"

namespace rig {
namespace {

using drivers::IoStatus;
using rt::CommandKind;
using rt::FaultCode;
using rt::RunState;

constexpr int kMaxFailedWrites = 6;  // not the default (3): the setting must be the one used

class LostWrites : public ::testing::Test {
 protected:
  void SetUp() override {
    rig_.physics().set_watchdog_ms(50);  // the DAQ's own watchdog must not decide these tests
    rig_.command(CommandKind::kHome);
    ASSERT_TRUE(rig_.run_until(
        [](const rt::StatusSnapshot& s) { return s.state == RunState::kReady; }, 60));
    rig_.command(CommandKind::kTare);
    ASSERT_TRUE(rig_.run_until([](const rt::StatusSnapshot& s) { return s.tared; }, 5));
    rt::RunParams params;
    params.run_id = 9;
    ASSERT_EQ(rig_.command(CommandKind::kArm, params), rt::CommandResult::kAccepted);
    const double surface = rig_.physics().params().tissue.surface_mm;
    ASSERT_TRUE(rig_.run_until(
        [surface](const rt::StatusSnapshot& s) { return s.position_mm > surface + 2.0; }, 30));
  }

  static rt::LoopSettings settings() {
    rt::LoopSettings loop = sim::loop_settings_for(sim::PhysicsParams{});
    loop.safety.max_failed_writes = kMaxFailedWrites;
    return loop;
  }

  // Cycles until the run faults (at most 100).
  int cycles_until_fault() {
    int cycles = 0;
    while (rig_.status().state != RunState::kFault && cycles < 100) {
      rig_.loop().run_for(rig_.loop().period_ns());
      ++cycles;
    }
    return cycles;
  }

  sim::SimulatedRig rig_{sim::PhysicsParams{}, {}, settings()};
};

TEST_F(LostWrites, LostWriteAnswersFaultTheRunOnlyAfterTheConfiguredNumberInARow) {
  rig_.daq().inject_write(IoStatus::kTimeout);
  for (int i = 0; i < kMaxFailedWrites; ++i) rig_.loop().run_for(rig_.loop().period_ns());
  EXPECT_EQ(rig_.status().state, RunState::kCutting)
      << kMaxFailedWrites << " lost writes: judged in the next cycle";
  const int more = cycles_until_fault();
  const rt::StatusSnapshot st = rig_.status();
  EXPECT_EQ(st.fault, FaultCode::kDaqWriteFailed);
  EXPECT_EQ(st.fault_value, static_cast<double>(kMaxFailedWrites));
  EXPECT_EQ(more, 1) << "faulted in the cycle after the last lost write";
  // Lost answers are the link's timing: the demo and the test harness may retry such a cut.
  const std::string text = service::describe_fault(st.fault, st.fault_value);
  EXPECT_EQ(text, "DAQ write failed: 6 writes in a row lost");
  EXPECT_TRUE(cli::is_timing_fault(text)) << text;
}

TEST_F(LostWrites, AWriteTakenAgainStartsTheCountAfresh) {
  rig_.daq().inject_write(IoStatus::kBadData);
  for (int i = 0; i < kMaxFailedWrites - 1; ++i) rig_.loop().run_for(rig_.loop().period_ns());
  rig_.daq().inject_write(IoStatus::kOk);
  rig_.loop().run_for(rig_.loop().period_ns());
  rig_.daq().inject_write(IoStatus::kBadData);
  for (int i = 0; i < kMaxFailedWrites - 1; ++i) rig_.loop().run_for(rig_.loop().period_ns());
  rig_.daq().inject_write(IoStatus::kOk);
  rig_.advance(0.01);
  EXPECT_EQ(rig_.status().state, RunState::kCutting) << "never " << kMaxFailedWrites << " in a row";
  EXPECT_GE(rig_.channels().counters.write_failures.load(), 2U * (kMaxFailedWrites - 1));
}

TEST_F(LostWrites, ARefusedWriteFaultsTheRunInTheNextCycleWhateverTheSetting) {
  rig_.daq().inject_write(IoStatus::kRefused);
  EXPECT_EQ(cycles_until_fault(), 2) << "the refusal is noted in one cycle, judged in the next";
  const rt::StatusSnapshot st = rig_.status();
  EXPECT_EQ(st.fault, FaultCode::kDaqWriteFailed);
  // A refusal is the DAQ's decision, never a timing matter: nothing retries it.
  const std::string text = service::describe_fault(st.fault, st.fault_value);
  EXPECT_EQ(text, "DAQ write failed: outputs refused by the DAQ");
  EXPECT_FALSE(cli::is_timing_fault(text)) << text;
}

}  // namespace
}  // namespace rig
