#pragma once
// The time source the control loop sleeps on: CLOCK_MONOTONIC on the rig, a virtual clock
// that advances the simulated physics in tests (faster than real time).
#include <cstdint>

namespace rig::drivers {

class LoopClock {
 public:
  virtual ~LoopClock() = default;
  virtual std::int64_t now_ns() noexcept = 0;
  // Sleeps until an absolute deadline [ns on this clock's time line]; returns at once if past.
  virtual void sleep_until(std::int64_t deadline_ns) noexcept = 0;
};

}  // namespace rig::drivers
