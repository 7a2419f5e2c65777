#include "rig/sim/motor_screw.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rig::sim {

double MotorScrew::mm_per_motor_rad() const {
  return p_.screw_pitch_mm / (2.0 * std::numbers::pi * p_.gear_ratio);
}

double MotorScrew::screw_angle_rad() const {
  const double turns = position_mm_ / p_.screw_pitch_mm;
  return 2.0 * std::numbers::pi * (turns - std::floor(turns));
}

void MotorScrew::step(double dt_s, double volts, bool enabled, double axial_load_N) {
  const double back_emf_V = p_.torque_constant_Nm_per_A * omega_rad_s_;
  // A disabled drive shorts the armature (dynamic braking), as most DC servo drives do.
  const double applied_V = enabled ? volts : 0.0;
  current_A_ = std::clamp((applied_V - back_emf_V) / p_.resistance_ohm, -p_.current_limit_A,
                          p_.current_limit_A);
  const double motor_torque_Nm = p_.torque_constant_Nm_per_A * current_A_;
  // Axial force [N] seen at the motor shaft through screw (m/rad) and gearbox.
  const double load_torque_Nm = axial_load_N *
                                (p_.screw_pitch_mm * 1e-3 / (2.0 * std::numbers::pi)) /
                                (p_.gear_ratio * p_.screw_efficiency);
  constexpr double kStictionSpeed_rad_s = 0.5;  // smoothing of the Coulomb friction sign
  const double friction_Nm = p_.coulomb_Nm * std::tanh(omega_rad_s_ / kStictionSpeed_rad_s) +
                             p_.viscous_Nms_per_rad * omega_rad_s_;
  double net_Nm = motor_torque_Nm - friction_Nm - load_torque_Nm;
  // A non-back-drivable screw does not start moving under load alone.
  if (std::abs(omega_rad_s_) < kStictionSpeed_rad_s &&
      std::abs(motor_torque_Nm - load_torque_Nm) < p_.coulomb_Nm) {
    net_Nm = -omega_rad_s_ * p_.inertia_kgm2 / dt_s;  // friction holds: stop within this step
  }
  omega_rad_s_ += net_Nm / p_.inertia_kgm2 * dt_s;
  position_mm_ += omega_rad_s_ * mm_per_motor_rad() * dt_s;
  if (position_mm_ < p_.travel_min_mm || position_mm_ > p_.travel_max_mm) {
    position_mm_ = std::clamp(position_mm_, p_.travel_min_mm, p_.travel_max_mm);
    omega_rad_s_ = 0.0;  // hit a hard stop
  }
}

}  // namespace rig::sim
