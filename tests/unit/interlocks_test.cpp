// Every interlock stops the motor within one loop period and keeps the run, measured in the
// simulated rig's physics on the virtual clock.
#include <gtest/gtest.h>

#include <iostream>

#include "simulated_rig.hpp"

namespace rig {
namespace {

using rt::CommandKind;
using rt::FaultCode;
using rt::RunState;

constexpr double kPeriod_s = 1e-3;
constexpr double kPhysicsStep_s = 1e-4;

class InterlockTest : public ::testing::Test {
 protected:
  void SetUp() override {
    rig_.physics().set_watchdog_ms(1);  // the DAQ's own watchdog: one loop period
    rig_.command(CommandKind::kHome);
    ASSERT_TRUE(rig_.run_until(
        [](const rt::StatusSnapshot& s) { return s.state == RunState::kReady; }, 60));
    rig_.command(CommandKind::kTare);
    ASSERT_TRUE(rig_.run_until([](const rt::StatusSnapshot& s) { return s.tared; }, 5));
    rt::RunParams params;
    params.run_id = 42;
    ASSERT_EQ(rig_.command(CommandKind::kArm, params), rt::CommandResult::kAccepted);
    const double surface = rig_.physics().params().tissue.surface_mm;
    ASSERT_TRUE(rig_.run_until(
        [surface](const rt::StatusSnapshot& s) { return s.position_mm > surface + 5.0; }, 30));
    ASSERT_TRUE(rig_.physics().truth().motor_powered);
    samples_.clear();
    events_.clear();
    rig_.drain(samples_, events_);
  }

  // Runs until the loop reacts; returns how long after `injected_at` the motor lost power.
  double motor_off_delay(double injected_at) {
    rig_.advance(0.05);
    rig_.drain(samples_, events_);
    const sim::RigTruth truth = rig_.physics().truth();
    EXPECT_FALSE(truth.motor_powered);
    const double delay = truth.motor_off_time_s - injected_at;
    EXPECT_GE(delay, 0.0) << "the motor must have been powered until the fault";
    std::cout << "motor off " << delay * 1e3 << " ms after the fault\n";
    return delay;
  }

  void expect_run_kept_with(FaultCode fault) {
    const rt::Event* ended = nullptr;
    for (const auto& e : events_) {
      if (e.kind == rt::EventKind::kRunEnded) {
        ended = &e;
        EXPECT_EQ(e.run_id, 42);
        EXPECT_EQ(e.fault, fault);
      }
    }
    ASSERT_NE(ended, nullptr) << "the run must be closed with the fault";
    ASSERT_GT(samples_.size(), 1000U) << "samples up to the fault are kept";
    const rt::Sample& last = samples_.back();
    EXPECT_EQ(last.run_id, 42);
    // The run keeps the cycle that ended it: the fault cycle's own sample, motor at 0 V.
    EXPECT_EQ(last.t_s, ended->t_s) << "the run's last sample is not the cycle that ended it";
    EXPECT_TRUE(last.state == RunState::kFault || last.state == RunState::kEStop)
        << rt::to_string(last.state);
    EXPECT_EQ(last.motor_volts, 0.0) << "the fault cycle commands 0 V";
  }

  sim::SimulatedRig rig_;
  std::vector<rt::Sample> samples_;
  std::vector<rt::Event> events_;
};

TEST_F(InterlockTest, EstopButtonMidCutStopsTheMotorWithinOnePeriod) {
  const double t = rig_.physics().time_s();
  rig_.physics().faults().estop_pressed = true;
  EXPECT_LE(motor_off_delay(t), kPeriod_s + kPhysicsStep_s);
  EXPECT_EQ(rig_.status().state, RunState::kEStop);
  expect_run_kept_with(FaultCode::kEstopInput);
}

TEST_F(InterlockTest, EndLimitSwitchMidCutStopsTheMotorWithinOnePeriod) {
  const double t = rig_.physics().time_s();
  rig_.physics().faults().end_limit_forced = true;
  EXPECT_LE(motor_off_delay(t), kPeriod_s + kPhysicsStep_s);
  EXPECT_EQ(rig_.status().fault, FaultCode::kEndLimit);
  expect_run_kept_with(FaultCode::kEndLimit);
}

TEST_F(InterlockTest, HomeLimitSwitchOutsideHomingStopsTheMotorWithinOnePeriod) {
  const double t = rig_.physics().time_s();
  rig_.physics().faults().home_limit_forced = true;
  EXPECT_LE(motor_off_delay(t), kPeriod_s + kPhysicsStep_s);
  EXPECT_EQ(rig_.status().fault, FaultCode::kHomeLimit);
}

TEST_F(InterlockTest, ForceOverloadStopsTheMotorWithinOnePeriodToProtectTheLoadCell) {
  const double t = rig_.physics().time_s();
  rig_.physics().faults().extra_force_N = 3.0;
  EXPECT_LE(motor_off_delay(t), kPeriod_s + kPhysicsStep_s);
  const rt::StatusSnapshot st = rig_.status();
  EXPECT_EQ(st.fault, FaultCode::kForceLimit);
  EXPECT_GT(st.fault_value, 2.0);
  expect_run_kept_with(FaultCode::kForceLimit);
}

TEST_F(InterlockTest, DaqLinkLossMidCutLeavesTheMotorOffWithinOnePeriodAndFaults) {
  const double t = rig_.physics().time_s();  // the last command reached the rig at t
  rig_.daq().inject(drivers::IoStatus::kLinkDown);
  EXPECT_LE(motor_off_delay(t), kPeriod_s + kPhysicsStep_s);  // the DAQ's watchdog
  EXPECT_EQ(rig_.status().fault, FaultCode::kLinkLost);
  expect_run_kept_with(FaultCode::kLinkLost);
}

TEST_F(InterlockTest, AStuckForceChannelWhileCuttingFaultsTheRun) {
  rig_.physics().faults().stuck_force = true;
  rig_.advance(0.2);
  rig_.drain(samples_, events_);
  EXPECT_EQ(rig_.status().fault, FaultCode::kStuckForce);
  EXPECT_FALSE(rig_.physics().truth().motor_powered);
  expect_run_kept_with(FaultCode::kStuckForce);
}

TEST_F(InterlockTest, AnIopLeakDuringTheCutFaultsTheRunOnceThePressureHasLeftItsBand) {
  rig_.physics().faults().iop_leak_fraction = 0.9;  // a burst line: the pump cannot hold 15 mmHg
  double left_band_at = -1.0;
  for (int ms = 0; ms < 3000 && rig_.physics().truth().motor_powered; ++ms) {
    rig_.advance(kPeriod_s);
    if (left_band_at < 0.0 && std::abs(rig_.status().iop_mmHg - 15.0) > 5.0)
      left_band_at = rig_.physics().time_s();
  }
  rig_.advance(0.01);  // the physics notes the motor-off time on its next step
  rig_.drain(samples_, events_);
  ASSERT_GE(left_band_at, 0.0) << "the leak never took the IOP out of its band";
  EXPECT_EQ(rig_.status().fault, FaultCode::kIopOutOfRange);
  const sim::RigTruth truth = rig_.physics().truth();
  ASSERT_FALSE(truth.motor_powered);
  const double delay = truth.motor_off_time_s - left_band_at;
  std::cout << "motor off " << delay * 1e3 << " ms after the IOP left its band\n";
  EXPECT_GE(delay, 0.1 - 2 * kPeriod_s)
      << "iop.fault_after_ms (100 ms) must pass first: a pump step is not a leak";
  EXPECT_LE(delay, 0.1 + 0.02) << "noise at the band edge may restart the count for a few cycles";
  expect_run_kept_with(FaultCode::kIopOutOfRange);
}

TEST_F(InterlockTest, AShortIopDipBelowFaultAfterMsDoesNotFaultTheRun) {
  rig_.physics().faults().iop_leak_fraction = 0.9;
  for (int ms = 0; ms < 3000 && std::abs(rig_.status().iop_mmHg - 15.0) <= 5.0; ++ms)
    rig_.advance(kPeriod_s);
  ASSERT_GT(std::abs(rig_.status().iop_mmHg - 15.0), 5.0)
      << "the leak never took the IOP out of its band";
  rig_.advance(0.03);  // 30 ms outside the band, then the leak closes
  rig_.physics().faults().iop_leak_fraction = 0.0;
  rig_.advance(1.0);
  EXPECT_NE(rig_.status().fault, FaultCode::kIopOutOfRange);
  EXPECT_EQ(rig_.status().state, RunState::kCutting);
}

TEST_F(InterlockTest, AnOverrunStormStopsTheMotor) {
  rig_.physics().set_watchdog_ms(5);  // shipped: a 3 ms late wake-up does not trip the DAQ
  // Each 3 ms late wake-up loses 3 deadlines of 4: the loop runs at a quarter of its rate until
  // 500 deadlines of the last 1000 are lost (the shipped storm), after about 170 of them.
  int late_wakes = 0;
  for (; late_wakes < 400 && rig_.status().state == RunState::kCutting; ++late_wakes) {
    rig_.clock().add_wakeup_delay(3'000'000);  // wake up 3 ms late
    rig_.loop().run_for(rig_.loop().period_ns());
  }
  rig_.advance(0.01);
  EXPECT_EQ(rig_.status().fault, FaultCode::kOverrunStorm);
  EXPECT_FALSE(rig_.physics().truth().motor_powered);
  EXPECT_GE(late_wakes, 160) << "not before 500 deadlines were lost";
  EXPECT_LE(late_wakes, 175) << "as soon as 500 deadlines were lost";
}

TEST_F(InterlockTest, LateCyclesOfABusyMachineAreCountedButALoopThatKeepsItsRateCutsOn) {
  // What a busy VM does to the loop: a cycle now and then ends after the next deadline and
  // skips it (here one in three, for 3 s), and a burst of 100 ms in which most are lost. The
  // carriage is still controlled, short stalls are the DAQ watchdog's (5 ms here): the run goes
  // on and every overrun is counted.
  rig_.physics().set_watchdog_ms(5);
  for (int i = 0; i < 1500; ++i) {
    if (i % 3 == 0) rig_.clock().add_wakeup_delay(1'500'000);  // 1.5 ms late: one deadline lost
    rig_.loop().run_for(rig_.loop().period_ns());
  }
  for (int i = 0; i < 30; ++i) {
    rig_.clock().add_wakeup_delay(3'000'000);  // 90 deadlines lost in 120 ms
    rig_.loop().run_for(rig_.loop().period_ns());
  }
  rig_.advance(0.01);
  EXPECT_EQ(rig_.status().state, RunState::kCutting) << rt::to_string(rig_.status().fault);
  EXPECT_GE(rig_.channels().counters.overruns.load(), 520U);
  EXPECT_GE(rig_.channels().counters.missed_cycles.load(), 580U);
}

TEST_F(InterlockTest, ASingleLateWakeUpIsCountedButDoesNotFaultTheRun) {
  rig_.physics().set_watchdog_ms(5);  // shipped: a 3 ms late wake-up does not trip the DAQ
  rig_.clock().add_wakeup_delay(3'000'000);
  rig_.advance(0.05);
  EXPECT_EQ(rig_.status().state, RunState::kCutting);
  EXPECT_EQ(rig_.channels().counters.overruns.load(), 1U);
}

TEST_F(InterlockTest, AfterAFaultOnlyAnExplicitResetLeavesFaultAndHomingIsNeededAgain) {
  rig_.physics().faults().extra_force_N = 3.0;
  rig_.advance(0.01);
  rig_.physics().faults().extra_force_N = 0.0;
  rig_.advance(1.0);
  EXPECT_EQ(rig_.status().state, RunState::kFault);
  EXPECT_EQ(rig_.command(CommandKind::kHome), rt::CommandResult::kFaulted);
  EXPECT_EQ(rig_.command(CommandKind::kReset), rt::CommandResult::kAccepted);
  EXPECT_EQ(rig_.status().state, RunState::kIdle);
  EXPECT_FALSE(rig_.status().homed);
  EXPECT_EQ(rig_.command(CommandKind::kArm, rt::RunParams{}), rt::CommandResult::kWrongState);
}

TEST_F(InterlockTest, AnEstopStaysLatchedWhileTheButtonIsPressed) {
  rig_.physics().faults().estop_pressed = true;
  rig_.advance(0.01);
  EXPECT_EQ(rig_.command(CommandKind::kReset), rt::CommandResult::kEstopPressed);
  EXPECT_EQ(rig_.status().state, RunState::kEStop);
  rig_.physics().faults().estop_pressed = false;
  EXPECT_EQ(rig_.command(CommandKind::kReset), rt::CommandResult::kAccepted);
  EXPECT_EQ(rig_.status().state, RunState::kIdle);
}

TEST_F(InterlockTest, StopMidCutStopsTheMotorAndEndsTheRunAsStopped) {
  const double t = rig_.physics().time_s();
  EXPECT_EQ(rig_.command(CommandKind::kStop), rt::CommandResult::kAccepted);
  EXPECT_LE(motor_off_delay(t), kPeriod_s + kPhysicsStep_s);
  EXPECT_EQ(rig_.status().state, RunState::kDone);
  bool stopped = false;
  for (const auto& e : events_)
    stopped = stopped || (e.kind == rt::EventKind::kRunEnded && e.value > 0.5);
  EXPECT_TRUE(stopped);
  // The blade is still in the eye: a new run needs homing first.
  EXPECT_EQ(rig_.command(CommandKind::kArm, rt::RunParams{}), rt::CommandResult::kNotAtPark);
}

// Control over the DAQ's outputs lost while it still answers reads (docs/faults.md).
TEST_F(InterlockTest, RefusedOutputWritesFaultTheRunBeforeTheDaqWatchdogAndItStopsTheMotor) {
  rig_.physics().set_watchdog_ms(5);         // the shipped setting: rigd must fault before it trips
  const double t = rig_.physics().time_s();  // the last accepted write
  rig_.physics().faults().writes_rejected = true;
  EXPECT_LE(motor_off_delay(t), 0.005 + 2 * kPhysicsStep_s)
      << "the DAQ's watchdog, as rigd cannot write";
  EXPECT_EQ(rig_.status().fault, FaultCode::kDaqWriteFailed);
  EXPECT_GE(rig_.channels().counters.write_failures.load(), 2U);
  expect_run_kept_with(FaultCode::kDaqWriteFailed);
}

TEST_F(InterlockTest, ADaqWatchdogTripFaultsTheRunAndTheMotorIsNeverPoweredAgain) {
  const double t = rig_.physics().time_s();
  rig_.physics().trip_watchdog();
  // motor_off_delay() takes the last power-off: a rigd that wrote the motor on again after
  // the trip would move it later than this.
  EXPECT_LE(motor_off_delay(t), kPeriod_s + kPhysicsStep_s);
  EXPECT_EQ(rig_.status().fault, FaultCode::kDaqWatchdogTripped);
  expect_run_kept_with(FaultCode::kDaqWatchdogTripped);
}

// The trip can fall between a cycle's read and its write: the host's next write ("motor on",
// computed before the trip) must not re-arm the DAQ before the host has read the bit.
TEST_F(InterlockTest, ADaqWatchdogTripBetweenReadAndWriteIsStillSeenAndTheMotorStaysOff) {
  const double t = rig_.physics().time_s();
  rig_.physics().trip_watchdog();
  drivers::DriveCommand motor_on;
  motor_on.motor_enable = true;
  motor_on.motor_volts = 1.0;
  drivers::DigitalOutputs enabled;
  enabled.motor_enable = true;
  rig_.physics().write_outputs(motor_on, enabled);
  EXPECT_FALSE(rig_.physics().truth().motor_powered)
      << "a write with the motor on re-armed the tripped DAQ";
  EXPECT_LE(motor_off_delay(t), kPeriod_s + kPhysicsStep_s);
  EXPECT_EQ(rig_.status().fault, FaultCode::kDaqWatchdogTripped);
  expect_run_kept_with(FaultCode::kDaqWatchdogTripped);
}

TEST_F(InterlockTest, ADaqRebootFaultsTheRunAndTheMotorIsNeverPoweredAgain) {
  const double t = rig_.physics().time_s();
  rig_.physics().restart_daq();  // outputs off, conversion counter from 0
  EXPECT_LE(motor_off_delay(t), kPeriod_s + kPhysicsStep_s);
  EXPECT_EQ(rig_.status().fault, FaultCode::kDaqRestarted);
  expect_run_kept_with(FaultCode::kDaqRestarted);
}

TEST_F(InterlockTest, ADriveFaultStopsTheMotorWithinOnePeriod) {
  const double t = rig_.physics().time_s();
  rig_.physics().faults().drive_fault = true;
  EXPECT_LE(motor_off_delay(t), kPeriod_s + kPhysicsStep_s);
  EXPECT_EQ(rig_.status().fault, FaultCode::kDriveFault);
  expect_run_kept_with(FaultCode::kDriveFault);
}

TEST_F(InterlockTest, APotentiometerReadingPastTheSoftLimitStopsTheMotorWithinOnePeriod) {
  const double t = rig_.physics().time_s();
  rig_.physics().faults().position_offset_mm = 30.0;  // reads beyond motion.soft_max_mm (44 mm)
  EXPECT_LE(motor_off_delay(t), kPeriod_s + kPhysicsStep_s);
  EXPECT_EQ(rig_.status().fault, FaultCode::kSoftLimit);
  EXPECT_GT(rig_.status().fault_value, 44.0);
  expect_run_kept_with(FaultCode::kSoftLimit);
}

TEST_F(InterlockTest, AJammedCarriageFaultsWithAFollowingErrorOnceItIsOneMillimetreBehind) {
  const double t = rig_.physics().time_s();
  rig_.physics().faults().carriage_jammed = true;
  rig_.advance(1.5);
  rig_.drain(samples_, events_);
  EXPECT_EQ(rig_.status().fault, FaultCode::kFollowingError);
  const sim::RigTruth truth = rig_.physics().truth();
  ASSERT_FALSE(truth.motor_powered);
  // safety.max_following_error_mm (1 mm) at the cut's 2 mm/s: 0.5 s, plus the loop's filter.
  const double delay = truth.motor_off_time_s - t;
  std::cout << "motor off " << delay * 1e3 << " ms after the jam\n";
  EXPECT_GE(delay, 0.45);
  EXPECT_LE(delay, 0.55);
  expect_run_kept_with(FaultCode::kFollowingError);
}

TEST(HomingTest, ABrokenHomeSwitchFailsHomingWhenTheCarriageStopsAtItsHardStop) {
  sim::SimulatedRig rig;
  rig.physics().set_watchdog_ms(1);
  rig.physics().faults().home_switch_broken = true;
  ASSERT_EQ(rig.command(CommandKind::kHome), rt::CommandResult::kAccepted);
  double stopped_at = -1.0;  // the carriage reached its hard stop
  const double hard_stop_mm = rig.physics().params().motor.travel_min_mm;
  for (int ms = 0; ms < 20000 && rig.status().state == RunState::kHoming; ++ms) {
    rig.advance(kPeriod_s);
    if (stopped_at < 0.0 && rig.physics().truth().carriage_mm <= hard_stop_mm + 1e-9)
      stopped_at = rig.physics().time_s();
  }
  rig.advance(0.01);
  ASSERT_GE(stopped_at, 0.0) << "the carriage never reached its hard stop";
  EXPECT_EQ(rig.status().state, RunState::kFault);
  EXPECT_EQ(rig.status().fault, FaultCode::kHomingFailed);
  EXPECT_FALSE(rig.status().homed);
  const sim::RigTruth truth = rig.physics().truth();
  ASSERT_FALSE(truth.motor_powered);
  // The reference runs on at motion.homing_velocity_mm_s (4 mm/s): 1 mm of following error in 0.25
  // s.
  const double delay = truth.motor_off_time_s - stopped_at;
  std::cout << "motor off " << delay * 1e3 << " ms after the carriage stopped\n";
  EXPECT_LE(delay, 0.25 + 0.05);
}

}  // namespace
}  // namespace rig
