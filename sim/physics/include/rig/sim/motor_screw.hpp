#pragma once
// DC motor driving a lead screw that moves the carriage. Electrical inductance is
// neglected (L/R << mechanical time constant); friction is Coulomb (smoothed) + viscous.
#include "rig/sim/physics_params.hpp"

namespace rig::sim {

class MotorScrew {
 public:
  explicit MotorScrew(const MotorScrewParams& params) : p_(params) {}

  // Advances by dt [s] with armature voltage `volts` [V] (ignored when disabled: the drive
  // then brakes dynamically) against an axial load on the carriage [N]
  // (positive = resisting motion into the eye).
  void step(double dt_s, double volts, bool enabled, double axial_load_N);

  double position_mm() const { return position_mm_; }
  double velocity_mm_s() const { return omega_rad_s_ * mm_per_motor_rad(); }
  double current_A() const { return current_A_; }
  void set_position_mm(double position_mm) { position_mm_ = position_mm; }
  // A seized screw: the carriage stays at position_mm and the shaft stands still.
  void seize_at(double position_mm) {
    position_mm_ = position_mm;
    omega_rad_s_ = 0.0;
  }
  double screw_angle_rad() const;  // screw angle modulo one turn [rad]

 private:
  double mm_per_motor_rad() const;
  MotorScrewParams p_;
  double omega_rad_s_ = 0.0;  // motor shaft speed
  double position_mm_ = 10.0;
  double current_A_ = 0.0;
};

}  // namespace rig::sim
