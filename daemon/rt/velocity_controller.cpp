#include "velocity_controller.hpp"

#include <algorithm>
#include <cmath>

namespace rig::rt {

void VelocityController::reset(double position_mm) noexcept {
  reference_mm_ = position_mm;
  measured_mm_ = position_mm;
  integral_V_ = 0.0;
}

double VelocityController::control(double velocity_mm_s, double measured_mm, double dt_s) noexcept {
  measured_mm_ = measured_mm;
  const double error_mm = reference_mm_ - measured_mm;
  const double unsaturated =
      gains_.feedforward_V_per_mm_s * velocity_mm_s + gains_.kp_V_per_mm * error_mm + integral_V_;
  const double volts = std::clamp(unsaturated, -gains_.max_volts, gains_.max_volts);
  // Anti-windup: integrate only while the output is not pushed further into saturation.
  if (volts == unsaturated || (unsaturated > volts) != (error_mm > 0.0)) {
    integral_V_ += gains_.ki_V_per_mm_s * error_mm * dt_s;
  }
  return volts;
}

double VelocityController::track_velocity(double velocity_mm_s, double measured_mm,
                                          double dt_s) noexcept {
  reference_mm_ += velocity_mm_s * dt_s;
  return control(velocity_mm_s, measured_mm, dt_s);
}

double VelocityController::move_to(double target_mm, double speed_mm_s, double measured_mm,
                                   double dt_s, bool& arrived) noexcept {
  const double remaining = target_mm - reference_mm_;
  const double step = std::min(std::abs(remaining), speed_mm_s * dt_s);
  const double velocity = remaining == 0.0 ? 0.0 : std::copysign(step / dt_s, remaining);
  reference_mm_ += std::copysign(step, remaining);
  const double volts = control(velocity, measured_mm, dt_s);
  constexpr double kArrivalTolerance_mm = 0.02;
  arrived = std::abs(target_mm - reference_mm_) < 1e-9 &&
            std::abs(target_mm - measured_mm) < kArrivalTolerance_mm;
  return volts;
}

}  // namespace rig::rt
