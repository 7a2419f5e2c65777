#include "virtual_clock.hpp"

namespace rig::drivers {

void VirtualClock::sleep_until(std::int64_t deadline_ns) noexcept {
  if (deadline_ns + extra_delay_ns_ > now_ns_) now_ns_ = deadline_ns + extra_delay_ns_;
  extra_delay_ns_ = 0;
  physics_->advance_to(static_cast<double>(now_ns_) * 1e-9);
}

}  // namespace rig::drivers
