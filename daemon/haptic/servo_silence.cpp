#include "servo_silence.hpp"

namespace rig::haptic {

double ServoSilence::poll(double now_ms, std::uint64_t ticks, bool running) {
  const double late_ms = now_ms - last_poll_ms_ - poll_ms_;  // the watchdog's own lateness
  last_poll_ms_ = now_ms;
  if (!started_ || ticks != last_ticks_ || !running) {
    started_ = true;
    last_ticks_ = ticks;
    last_progress_ms_ = now_ms;
    return 0.0;
  }
  // A poll more than a period late: the watchdog was off the CPU and cannot tell whether the
  // servo would have ticked meanwhile. That time is not counted against the servo.
  if (late_ms > poll_ms_) last_progress_ms_ += late_ms;
  return now_ms - last_progress_ms_;
}

}  // namespace rig::haptic
