#pragma once
// A loop clock whose sleeps advance the simulated rig instead of waiting: a 10 s cut runs
// in a fraction of a second and every run is deterministic.
#include "rig/drivers/loop_clock.hpp"
#include "rig/sim/rig_physics.hpp"

namespace rig::drivers {

class VirtualClock final : public LoopClock {
 public:
  explicit VirtualClock(sim::RigPhysics& physics) : physics_(&physics) {}
  std::int64_t now_ns() noexcept override { return now_ns_; }
  void sleep_until(std::int64_t deadline_ns) noexcept override;
  // Lets a test delay the loop's next wake-up (a late wake-up / overrun) [ns].
  void add_wakeup_delay(std::int64_t delay_ns) noexcept { extra_delay_ns_ += delay_ns; }
  // Time passes now, mid-cycle, as when the machine holds the loop off the CPU [ns].
  void stall(std::int64_t duration_ns) noexcept { now_ns_ += duration_ns; }

 private:
  sim::RigPhysics* physics_;
  std::int64_t now_ns_ = 0;
  std::int64_t extra_delay_ns_ = 0;
};

}  // namespace rig::drivers
