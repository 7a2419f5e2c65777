#include "wall_clock_sim_daq.hpp"

namespace rig::drivers {

WallClockSimDaq::WallClockSimDaq(const sim::PhysicsParams& params)
    : start_ns_(clock_.now_ns()), physics_(params), daq_(physics_) {}

IoStatus WallClockSimDaq::read(AnalogFrame& frame) noexcept {
  physics_.advance_to(static_cast<double>(clock_.now_ns() - start_ns_) * 1e-9);
  return daq_.read(frame);
}

}  // namespace rig::drivers
