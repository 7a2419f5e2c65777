#pragma once
// Holds the commanded keratome velocity: a reference position advances at the commanded
// velocity and the motor voltage is feed-forward (back-EMF per velocity) + PI on the
// potentiometer's position error. Tracking a position reference rather than a noisy
// velocity estimate makes the mean velocity exact over a cut. No allocation, no branches
// on the failure path beyond saturation.
#include "loop_settings.hpp"

namespace rig::rt {

class VelocityController {
 public:
  explicit VelocityController(const ControllerGains& gains) : gains_(gains) {}

  void reset(double position_mm) noexcept;
  // Reference moves at velocity [mm/s]; returns the motor voltage [V].
  double track_velocity(double velocity_mm_s, double measured_mm, double dt_s) noexcept;
  // Reference moves towards target at speed; `arrived` once reference and carriage are there.
  double move_to(double target_mm, double speed_mm_s, double measured_mm, double dt_s,
                 bool& arrived) noexcept;
  double reference_mm() const noexcept { return reference_mm_; }
  double following_error_mm() const noexcept { return reference_mm_ - measured_mm_; }

 private:
  double control(double velocity_mm_s, double measured_mm, double dt_s) noexcept;
  ControllerGains gains_;
  double reference_mm_ = 0.0;
  double integral_V_ = 0.0;
  double measured_mm_ = 0.0;
};

}  // namespace rig::rt
