#pragma once
// The simulated rig's DAQ on the real clock: every read advances the physics to "now"
// (CLOCK_MONOTONIC since construction). For a control loop that runs in real time against
// in-process physics (benchmarks, kernel-tier tests) instead of a virtual clock.
#include <cstdint>

#include "clock/monotonic_clock.hpp"
#include "rig/sim/rig_physics.hpp"
#include "sim_daq.hpp"

namespace rig::drivers {

class WallClockSimDaq final : public AnalogInput, public DigitalIo, public ActuatorDrive {
 public:
  explicit WallClockSimDaq(const sim::PhysicsParams& params = {});

  IoStatus read(AnalogFrame& frame) noexcept override;
  IoStatus read(DigitalInputs& inputs) noexcept override { return daq_.read(inputs); }
  IoStatus write(const DigitalOutputs& outputs) noexcept override { return daq_.write(outputs); }
  IoStatus write(const DriveCommand& command) noexcept override { return daq_.write(command); }
  sim::RigPhysics& physics() noexcept { return physics_; }  // only from the loop's thread

 private:
  MonotonicClock clock_;
  std::int64_t start_ns_ = 0;
  sim::RigPhysics physics_;
  SimDaq daq_;
};

}  // namespace rig::drivers
