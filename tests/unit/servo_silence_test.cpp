// The haptic stall watchdog's judgement on a virtual clock [ms]: a stuck servo is silent from
// its last tick; the watchdog's own time off the CPU is not the servo's silence.
#include <gtest/gtest.h>

#include "servo_silence.hpp"

namespace rig::haptic {
namespace {

constexpr double kPoll_ms = 2.0;

TEST(ServoSilence, AServoThatStopsTickingIsSilentFromItsLastTickOnAPunctualWatchdog) {
  ServoSilence silence(kPoll_ms);
  std::uint64_t ticks = 0;
  double t = 0.0;
  for (; t <= 10.0; t += kPoll_ms)
    EXPECT_EQ(silence.poll(t, ticks += 2, true), 0.0) << "ticking at " << t << " ms";
  const double last_tick_ms = t - kPoll_ms;
  for (; t <= 40.0; t += kPoll_ms) EXPECT_DOUBLE_EQ(silence.poll(t, ticks, true), t - last_tick_ms);
}

TEST(ServoSilence, AWatchdogThatWasItselfOffTheCpuDoesNotBlameTheServoForTheMachinesStall) {
  ServoSilence silence(kPoll_ms);
  silence.poll(0.0, 1, true);
  silence.poll(2.0, 2, true);
  // The whole machine stands still for 50 ms; the watchdog wakes before the servo has ticked.
  EXPECT_LT(silence.poll(54.0, 2, true), 20.0) << "a 20 ms watchdog must not trip on the stall";
  EXPECT_EQ(silence.poll(56.0, 3, true), 0.0) << "the servo ticks again";
}

TEST(ServoSilence, AStuckServoStillTripsOneTimeoutAfterALateWatchdogIsBack) {
  ServoSilence silence(kPoll_ms);
  silence.poll(0.0, 7, true);  // the servo's last tick
  const double after_stall = silence.poll(50.0, 7, true);
  EXPECT_LT(after_stall, 20.0);
  double t = 50.0, gap = after_stall;
  while (gap <= 20.0 && t < 200.0) gap = silence.poll(t += kPoll_ms, 7, true);
  EXPECT_LE(t, 50.0 + 20.0 + kPoll_ms) << "tripped within a timeout of the watchdog's return";
}

TEST(ServoSilence, ADeviceThatIsNotRunningIsNeverSilent) {
  ServoSilence silence(kPoll_ms);
  silence.poll(0.0, 5, false);
  EXPECT_EQ(silence.poll(30.0, 5, false), 0.0);
  EXPECT_DOUBLE_EQ(silence.poll(32.0, 5, true), 2.0) << "silence counts from when it last ran";
  EXPECT_DOUBLE_EQ(silence.poll(34.0, 5, true), 4.0);
}

}  // namespace
}  // namespace rig::haptic
