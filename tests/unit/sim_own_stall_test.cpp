// rig-sim off the CPU (a busy host): the simulated world moves on through the stall in real
// time, as rigd's velocity reference does, while the DAQ's watchdog and the tests' latency
// clock excuse it. Frozen instead, the world fell behind rigd's reference by v x stall and
// homing failed on a following error that no real rig has (CI, 2026-12-03).
#include <gtest/gtest.h>

#include "rig/sim/rig_physics.hpp"

namespace rig::sim {
namespace {

constexpr double kStall_s = 0.2;

class OwnStallTest : public ::testing::Test {
 protected:
  void SetUp() override {
    physics_.set_watchdog_ms(5);
    physics_.place_carriage(5.0);  // [mm] in free travel, short of the cornea
    // rigd writes every 1 ms for 0.3 s: the motor reaches a steady speed.
    for (int k = 1; k <= 300; ++k) {
      physics_.write_outputs(drive_, outputs_);
      physics_.advance_to(k * 1e-3);
    }
  }
  RigPhysics physics_{PhysicsParams{}};
  drivers::DriveCommand drive_{true, 6.0, 0.0};  // [V] forward
  drivers::DigitalOutputs outputs_ = [] {
    drivers::DigitalOutputs o{};
    o.motor_enable = true;
    return o;
  }();
};

TEST_F(OwnStallTest, TheWorldMovesOnThroughTheSimulatorsOwnStallAndTheDaqWatchdogExcusesIt) {
  const RigTruth before = physics_.truth();
  ASSERT_TRUE(before.motor_powered);
  ASSERT_GT(before.velocity_mm_s, 0.1);
  physics_.excuse_own_stall(kStall_s);
  physics_.advance_to(before.time_s + kStall_s);
  const RigTruth after = physics_.truth();
  EXPECT_TRUE(after.motor_powered)
      << "a 200 ms stall of rig-sim is not 200 ms of silence from rigd";
  EXPECT_FALSE(after.watchdog_tripped);
  EXPECT_NEAR(after.carriage_mm - before.carriage_mm, before.velocity_mm_s * kStall_s,
              0.1 * before.velocity_mm_s * kStall_s)
      << "the carriage ran on at its speed";
  EXPECT_NEAR(after.time_s - after.accountable_time_s, kStall_s, 1e-9)
      << "accountable time leaves the stall out";
}

TEST_F(OwnStallTest, RigdsOwnSilenceAfterTheStallStillTripsTheWatchdogOnTime) {
  physics_.excuse_own_stall(kStall_s);
  const double stalled_until_s = physics_.time_s() + kStall_s;
  physics_.advance_to(stalled_until_s);
  physics_.write_outputs(drive_, outputs_);  // rigd's queued write, heard as rig-sim wakes
  const double last_write_accountable_s = physics_.truth().accountable_time_s;
  physics_.advance_to(stalled_until_s + 0.02);  // then rigd falls silent for 20 ms
  const RigTruth silent = physics_.truth();
  EXPECT_TRUE(silent.watchdog_tripped);
  EXPECT_FALSE(silent.motor_powered);
  EXPECT_NEAR(silent.motor_off_time_s - last_write_accountable_s, 0.005, 0.0011)
      << "motor off one watchdog period (5 ms) after rigd's last write, on the accountable clock";
}

}  // namespace
}  // namespace rig::sim
