#pragma once
// The DAQ of the simulated rig, in-process: the same interfaces as the Modbus DAQ, over
// RigPhysics, with link faults a test can inject. Used with VirtualClock so the whole
// control loop runs faster than real time.
#include "rig/drivers/actuator_drive.hpp"
#include "rig/drivers/analog_input.hpp"
#include "rig/drivers/digital_io.hpp"
#include "rig/sim/rig_physics.hpp"
#include "virtual_clock.hpp"

namespace rig::drivers {

class SimDaq final : public AnalogInput, public ActuatorDrive, public DigitalIo {
 public:
  explicit SimDaq(sim::RigPhysics& physics) : physics_(&physics) {}

  IoStatus read(AnalogFrame& frame) noexcept override;
  IoStatus read(DigitalInputs& inputs) noexcept override;
  IoStatus write(const DigitalOutputs& outputs) noexcept override;
  IoStatus write(const DriveCommand& command) noexcept override;

  // Every call fails with this status until cleared with kOk (link loss, time-outs, garbage).
  void inject(IoStatus failure) noexcept { injected_ = failure; }
  // Only output writes fail with this status (their answers lost or garbled, or refused) while
  // reads are answered, until cleared with kOk; a failed write never reaches the rig.
  void inject_write(IoStatus failure) noexcept { write_injected_ = failure; }
  // Every analog read takes this long on `clock` (a slow exchange, or the loop held off the
  // CPU while it waits for the reply) until set back to 0 [ns].
  void take_per_read(VirtualClock& clock, std::int64_t duration_ns) noexcept {
    read_clock_ = &clock;
    read_duration_ns_ = duration_ns;
  }

 private:
  sim::RigPhysics* physics_;
  IoStatus injected_ = IoStatus::kOk;
  IoStatus write_injected_ = IoStatus::kOk;
  DigitalOutputs staged_{};
  VirtualClock* read_clock_ = nullptr;
  std::int64_t read_duration_ns_ = 0;
};

}  // namespace rig::drivers
