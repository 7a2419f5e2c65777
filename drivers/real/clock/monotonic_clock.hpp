#pragma once
#include "rig/drivers/loop_clock.hpp"

namespace rig::drivers {

// clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME): absolute deadlines do not accumulate
// the drift of relative sleeps.
class MonotonicClock final : public LoopClock {
 public:
  std::int64_t now_ns() noexcept override;
  void sleep_until(std::int64_t deadline_ns) noexcept override;
};

}  // namespace rig::drivers
