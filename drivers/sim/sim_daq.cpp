#include "sim_daq.hpp"

namespace rig::drivers {

IoStatus SimDaq::read(AnalogFrame& frame) noexcept {
  if (read_clock_ != nullptr && read_duration_ns_ > 0) read_clock_->stall(read_duration_ns_);
  if (injected_ != IoStatus::kOk) return injected_;
  frame = physics_->analog_frame();
  return IoStatus::kOk;
}

IoStatus SimDaq::read(DigitalInputs& inputs) noexcept {
  if (injected_ != IoStatus::kOk) return injected_;
  inputs = physics_->digital_inputs();
  return IoStatus::kOk;
}

IoStatus SimDaq::write(const DigitalOutputs& outputs) noexcept {
  staged_ = outputs;
  return injected_;
}

IoStatus SimDaq::write(const DriveCommand& command) noexcept {
  if (injected_ != IoStatus::kOk) return injected_;  // the command never reaches the rig
  if (write_injected_ != IoStatus::kOk) return write_injected_;
  if (physics_->faults().writes_rejected) return IoStatus::kRefused;
  physics_->write_outputs(command, staged_);
  return IoStatus::kOk;
}

}  // namespace rig::drivers
