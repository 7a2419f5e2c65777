#include "iop_regulator.hpp"

#include <algorithm>
#include <cmath>

namespace rig::rt {

void IopRegulator::set_target(double target_mmHg) noexcept {
  if (!active_ || target_mmHg != target_mmHg_) {
    settled_ = false;
    in_band_s_ = 0.0;
    since_target_s_ = 0.0;
  }
  target_mmHg_ = target_mmHg;
  active_ = true;
}

void IopRegulator::disable() noexcept {
  active_ = false;
  settled_ = false;
  integral_ = 0.0;
  in_band_s_ = 0.0;
}

double IopRegulator::update(double measured_mmHg, double dt_s) noexcept {
  if (!active_) return 0.0;
  since_target_s_ += dt_s;
  const double error = target_mmHg_ - measured_mmHg;
  const double feedforward = target_mmHg_ / s_.pump_full_scale_mmHg;
  const double unsaturated = feedforward + s_.kp_per_mmHg * error + integral_;
  const double command = std::clamp(unsaturated, 0.0, 1.0);
  if (command == unsaturated) integral_ += s_.ki_per_mmHg_s * error * dt_s;
  in_band_s_ = std::abs(error) <= s_.settle_band_mmHg ? in_band_s_ + dt_s : 0.0;
  // Once settled, the flag stays until the target changes: cut-induced excursions are
  // watched by the fault band instead.
  if (in_band_s_ >= s_.settle_time_s) settled_ = true;
  return command;
}

}  // namespace rig::rt
