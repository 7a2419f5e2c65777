// Two faults no simulated rig can show from outside rigd, measured in-process on the virtual
// clock: an IOP that never settles while armed (kIopNotSettled; the fault matrix injects the
// same leak through rig-sim, here it is cycle-exact), and a recorder that stops taking samples
// (kRecorderOverflow: the ring between the loop and the recorder is full).
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

#include "simulated_rig.hpp"

namespace rig::armed_and_recorder_faults {  // named: test_interlocks is a unity build
namespace {

using rt::CommandKind;
using rt::FaultCode;
using rt::RunState;

constexpr double kPeriod_s = 1e-3;
constexpr double kPhysicsStep_s = 1e-4;

void home_and_tare(sim::SimulatedRig& rig) {
  rig.command(CommandKind::kHome);
  ASSERT_TRUE(
      rig.run_until([](const rt::StatusSnapshot& s) { return s.state == RunState::kReady; }, 60));
  rig.command(CommandKind::kTare);
  ASSERT_TRUE(rig.run_until([](const rt::StatusSnapshot& s) { return s.tared; }, 5));
}

TEST(ArmedRunFaults,
     AnIopThatCannotReachItsTargetFaultsTheArmedRunAtTheSettleTimeOutWithTheMotorNeverOn) {
  sim::SimulatedRig rig;
  ASSERT_NO_FATAL_FAILURE(home_and_tare(rig));
  const double settle_timeout_s =
      sim::loop_settings_for(rig.physics().params()).iop.settle_timeout_s;
  rig.physics().faults().iop_leak_fraction = 0.9;  // a burst line: 4 mmHg at most, the run asks 15
  const double motor_off_before_s = rig.physics().truth().motor_off_time_s;
  rt::RunParams params;
  params.run_id = 7;
  ASSERT_EQ(rig.command(CommandKind::kArm, params), rt::CommandResult::kAccepted);
  rig.advance(settle_timeout_s - 2 * kPeriod_s);
  EXPECT_EQ(rig.status().state, RunState::kArmed) << "faulted before iop.settle_timeout_s";
  ASSERT_TRUE(
      rig.run_until([](const rt::StatusSnapshot& s) { return s.state == RunState::kFault; }, 0.05));
  const rt::StatusSnapshot st = rig.status();
  EXPECT_EQ(st.fault, FaultCode::kIopNotSettled);
  EXPECT_LT(st.fault_value, 15.0 - 5.0) << "the fault carries the pressure reached [mmHg]";
  std::vector<rt::Sample> samples;
  std::vector<rt::Event> events;
  rig.drain(samples, events);
  double armed_at_s = -1.0, faulted_at_s = -1.0;  // the loop's clock [s]
  for (const auto& e : events) {
    if (e.kind == rt::EventKind::kCommand && e.command == CommandKind::kArm) armed_at_s = e.t_s;
    if (e.kind == rt::EventKind::kFault) faulted_at_s = e.t_s;
    EXPECT_NE(e.kind, rt::EventKind::kRunStarted) << "the cut started without a settled IOP";
  }
  ASSERT_GE(armed_at_s, 0.0) << "no arm event";
  ASSERT_GE(faulted_at_s, 0.0) << "no fault event";
  // The fault comes at the time-out, in the cycle that passes it.
  EXPECT_NEAR(faulted_at_s - armed_at_s, settle_timeout_s, 2 * kPeriod_s);
  EXPECT_TRUE(std::none_of(samples.begin(), samples.end(), [](const rt::Sample& s) {
    return s.run_id == 7;
  })) << "an unstarted run has no samples";
  EXPECT_FALSE(rig.physics().truth().motor_powered);
  EXPECT_EQ(rig.physics().truth().motor_off_time_s, motor_off_before_s)
      << "the motor ran while armed";
}

// The shipped ring (2^16 samples, 65 s at 1 kHz) filled by a recorder that takes nothing: the
// cut holds at depth long enough (120 s) for the ring to fill while the motor holds the blade.
TEST(RecorderFaults,
     ARecorderThatStopsTakingSamplesFaultsTheRunInTheCycleTheRingIsFullAndKeepsEverySampleBefore) {
  sim::SimulatedRig rig;
  ASSERT_NO_FATAL_FAILURE(home_and_tare(rig));
  rt::RunParams params;
  params.run_id = 9;
  params.hold_s = 120.0;
  ASSERT_EQ(rig.command(CommandKind::kArm, params), rt::CommandResult::kAccepted);
  std::vector<rt::Sample> samples;
  std::vector<rt::Event> events;
  rig.drain(samples, events);  // armed: no run samples yet, only events
  const std::size_t capacity = rig.channels().recorder.capacity();
  double failing_cycle_at_s = -1.0;
  bool powered_before = false;
  for (int ms = 0; ms < 90'000 && rig.channels().counters.recorder_drops.load() == 0; ++ms) {
    failing_cycle_at_s = rig.physics().time_s();
    powered_before = rig.physics().truth().motor_powered;
    rig.advance(kPeriod_s);
  }
  ASSERT_EQ(rig.channels().counters.recorder_drops.load(), 1U) << "the ring never filled";
  EXPECT_TRUE(powered_before) << "the motor must hold the blade until the ring is full";
  rig.advance(0.01);  // the physics notes the motor-off time on its next step
  const rt::StatusSnapshot st = rig.status();
  EXPECT_EQ(st.state, RunState::kFault);
  EXPECT_EQ(st.fault, FaultCode::kRecorderOverflow);
  EXPECT_EQ(st.fault_value, static_cast<double>(capacity))
      << "the fault names the ring's size [samples]";
  const sim::RigTruth truth = rig.physics().truth();
  ASSERT_FALSE(truth.motor_powered);
  const double delay_s = truth.motor_off_time_s - failing_cycle_at_s;
  std::cout << "motor off " << delay_s * 1e3
            << " ms after the cycle whose sample found the ring full\n";
  EXPECT_GE(delay_s, 0.0);
  EXPECT_LE(delay_s, kPeriod_s + kPhysicsStep_s) << "the motor stops in the cycle of the overflow";
  rig.drain(samples, events);
  const auto run_samples = std::count_if(samples.begin(), samples.end(),
                                         [](const rt::Sample& s) { return s.run_id == 9; });
  EXPECT_EQ(static_cast<std::size_t>(run_samples), capacity)
      << "every sample that fitted is kept, none after";
  for (std::size_t i = 1; i < samples.size(); ++i)
    ASSERT_EQ(samples[i].cycle, samples[i - 1].cycle + 1) << "a gap";
  const auto ended = std::find_if(events.begin(), events.end(), [](const rt::Event& e) {
    return e.kind == rt::EventKind::kRunEnded;
  });
  ASSERT_NE(ended, events.end()) << "the run must be closed with the fault";
  EXPECT_EQ(ended->fault, FaultCode::kRecorderOverflow);
}

}  // namespace
}  // namespace rig::armed_and_recorder_faults
