#pragma once
// Zeroes the force if the servo stops ticking: a stuck source, a preempted thread or a
// dead device scheduler must not leave the last force on the trainee's hand. Its own
// thread polls the device's tick counter every poll period; no progress for `timeout`
// turns force output off at the device (HapticDevice::force_off is safe from any thread).
// The watchdog's own late wake-ups are not counted as the servo's silence (servo_silence.hpp).
// A timeout of 0 turns it off: for a simulated device on virtual time, where no hand holds
// anything and wall-clock stalls of the (unthrottled) servo thread mean nothing.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "rig/drivers/haptic_device.hpp"

namespace rig::haptic {

class StallWatchdog {
 public:
  StallWatchdog(drivers::HapticDevice& device, std::chrono::milliseconds timeout,
                std::chrono::milliseconds poll = std::chrono::milliseconds(2));
  ~StallWatchdog();
  void start();
  void stop() noexcept;
  bool tripped() const noexcept { return tripped_.load(); }
  double longest_gap_ms() const noexcept { return longest_gap_ms_.load(); }

 private:
  void run() noexcept;

  drivers::HapticDevice& device_;
  std::chrono::milliseconds timeout_, poll_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::atomic<bool> tripped_{false};
  std::atomic<double> longest_gap_ms_{0.0};
};

}  // namespace rig::haptic
