#pragma once
// How long the haptic servo has been silent, as its stall watchdog judges it [ms]: time since
// the device's tick counter last moved, less the watchdog's own late wake-ups. A watchdog that
// was itself off the CPU saw nothing in that time: when the whole machine stood still (a VM's
// host holds both vCPUs, 10-100 ms), the watchdog can wake before the servo and would blame it
// for the machine's stall (CI, 2026-12-03: "servo stalled" 0.4 s into a healthy session).
// Excused, a servo that is really stuck still trips one timeout after the watchdog is back.
// Plain arithmetic on times passed in, so it is tested on a virtual clock.
#include <cstdint>

namespace rig::haptic {

class ServoSilence {
 public:
  explicit ServoSilence(double poll_ms) : poll_ms_(poll_ms) {}
  // One poll at now_ms [ms, any monotonic clock] with the device's tick counter and whether it
  // runs; returns the servo's silence [ms] (0 while it ticks or is not running).
  double poll(double now_ms, std::uint64_t ticks, bool running);

 private:
  double poll_ms_;  // the watchdog's poll period [ms]
  bool started_ = false;
  double last_poll_ms_ = 0.0;
  double last_progress_ms_ = 0.0;
  std::uint64_t last_ticks_ = 0;
};

}  // namespace rig::haptic
