#include "rig/sim/rig_physics.hpp"

#include <cmath>

namespace rig::sim {

RigPhysics::RigPhysics(const PhysicsParams& params, const std::vector<HiddenEffect>& effects)
    : params_(params),
      effects_(effects),
      rng_(params.seed),
      motor_(params.motor),
      tissue_(params.tissue, effects_),
      iop_(params.iop),
      sensors_(params.sensors, effects_, params.motor.screw_pitch_mm) {
  motor_.set_position_mm(params.tissue.surface_mm - 8.0);
  mount_new_eye(next_covariate_);
  frame_ = sensors_.convert(
      TrueSignals{0.0, motor_.position_mm(), iop_.pressure_mmHg(), 0.0, 0.0, 0.0}, rng_);
}

void RigPhysics::mount_new_eye(double covariate_value) {
  effects_.set_covariate_value(covariate_value);
  effects_.new_run(rng_);
  tissue_.new_eye(rng_);
  sensors_.new_eye();
  eye_mounted_s_ = time_s_;
  outside_idle_s_ = 0.0;
}

bool RigPhysics::watchdog_tripped() const {
  // Half a step of slack: silence is a whole number of steps, summed in floating point.
  return watchdog_trip_latched_ ||
         (watchdog_s_ > 0.0 && time_s_ - last_write_s_ > watchdog_s_ + 0.5 * params_.step_s);
}

bool RigPhysics::motor_powered() const {
  return drive_.motor_enable && digital_out_.motor_enable && !watchdog_tripped();
}

void RigPhysics::restart_daq() {
  drive_ = {};
  digital_out_ = {};
  watchdog_s_ = 0.0;
  watchdog_trip_latched_ = false;
  sequence_ = 0;
}

void RigPhysics::trip_watchdog() {
  drive_ = {};
  digital_out_ = {};
  watchdog_trip_latched_ = true;
}

void RigPhysics::excuse_own_stall(double stall_s) {
  if (!(stall_s > 0.0)) return;
  last_write_s_ += stall_s;
  excused_stalls_s_ += stall_s;
}

void RigPhysics::write_outputs(const drivers::DriveCommand& drive,
                               const drivers::DigitalOutputs& digital) {
  if (digital.camera_trigger && !digital_out_.camera_trigger) ++trigger_edges_;
  drive_ = drive;
  digital_out_ = digital;
  last_write_s_ = time_s_;
  // A tripped DAQ re-arms only when the host writes safe outputs (motor disabled), as a
  // latched watchdog does: a host that keeps writing "motor on" must read the bit, not have
  // its next write clear it unseen (the trip can fall between a cycle's read and its write).
  if (!drive.motor_enable || !digital.motor_enable) watchdog_trip_latched_ = false;
}

drivers::DigitalInputs RigPhysics::digital_inputs() const {
  drivers::DigitalInputs inputs;
  const double x = motor_.position_mm();
  inputs.home_limit = !faults_.home_switch_broken &&
                      (faults_.home_limit_forced || x <= params_.switches.home_switch_mm);
  inputs.end_limit = faults_.end_limit_forced || x >= params_.switches.end_switch_mm;
  inputs.estop = faults_.estop_pressed;
  inputs.drive_fault = faults_.drive_fault;
  inputs.daq_watchdog_tripped = watchdog_tripped();
  return inputs;
}

void RigPhysics::maybe_swap_eye() {
  // The technician mounts a fresh eye once a cut eye is out of reach and the carriage rests.
  const bool outside = tissue_.tip_depth_mm() < -0.5;
  const bool resting = std::abs(motor_.velocity_mm_s()) < 0.01;
  outside_idle_s_ =
      (outside && resting && tissue_.punctured()) ? outside_idle_s_ + params_.step_s : 0.0;
  if (auto_new_eye_ && outside_idle_s_ > 0.5) mount_new_eye(next_covariate_);
}

void RigPhysics::step_once() {
  const double dt = params_.step_s;
  const bool powered = motor_powered();
  if (was_powered_ && !powered) {
    motor_off_time_s_ = time_s_ - excused_stalls_s_;
    motor_off_silence_s_ = time_s_ - last_write_s_;  // stalls already excused from both
  }
  was_powered_ = powered;
  const double before_mm = motor_.position_mm();
  motor_.step(dt, drive_.motor_volts, powered, tissue_.force_N());
  if (faults_.carriage_jammed) motor_.seize_at(before_mm);
  TissueInput input;
  input.carriage_depth_mm = motor_.position_mm() - params_.tissue.surface_mm;
  input.velocity_mm_s = motor_.velocity_mm_s();
  input.iop_mmHg = iop_.pressure_mmHg();
  input.dt_s = dt;
  input.run_time_s = time_s_ - eye_mounted_s_;
  tissue_.update(input, rng_);
  iop_.step(dt, drive_.pump_command, tissue_.punctured(), faults_.iop_leak_fraction);
  time_s_ += dt;
  maybe_swap_eye();

  TrueSignals truth{tissue_.force_N() + faults_.extra_force_N,
                    motor_.position_mm() + faults_.position_offset_mm,
                    iop_.pressure_mmHg(),
                    time_s_,
                    time_s_ - eye_mounted_s_,
                    motor_.velocity_mm_s()};
  sensors_.advance(dt);
  const drivers::AnalogFrame fresh = sensors_.convert(truth, rng_);
  const double stuck_force_V = frame_.force_volts;
  frame_ = fresh;
  if (faults_.stuck_force) frame_.force_volts = stuck_force_V;
  frame_.sequence = ++sequence_;
}

void RigPhysics::advance_to(double time_s) {
  while (time_s_ + 0.5 * params_.step_s < time_s) step_once();
}

RigTruth RigPhysics::truth() const {
  RigTruth t;
  t.time_s = time_s_;
  t.carriage_mm = motor_.position_mm();
  t.velocity_mm_s = motor_.velocity_mm_s();
  t.tip_depth_mm = tissue_.tip_depth_mm();
  t.force_N = tissue_.force_N();
  t.iop_mmHg = iop_.pressure_mmHg();
  t.punctured = tissue_.punctured();
  t.motor_powered = motor_powered();
  t.motor_off_time_s = motor_off_time_s_;
  t.motor_off_silence_s = motor_off_silence_s_;
  t.accountable_time_s = time_s_ - excused_stalls_s_;
  t.watchdog_tripped = watchdog_tripped();
  t.camera_trigger_edges = trigger_edges_;
  return t;
}

}  // namespace rig::sim
