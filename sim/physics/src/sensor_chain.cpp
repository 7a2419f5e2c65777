#include "rig/sim/sensor_chain.hpp"

#include <cmath>

#include "rig/sim/effect_forms.hpp"

namespace rig::sim {
double SensorChain::instrument_force_N(const TrueSignals& truth) const {
  double force = truth.force_N;
  const EffectSlot& drift = (*effects_)[EffectKind::kSensorDrift];
  if (drift.on) force += forms::drift_N(drift, truth.run_time_s, random_walk_N_);
  const EffectSlot& ripple = (*effects_)[EffectKind::kSpatialRipple];
  if (ripple.on)
    force += forms::ripple_N(ripple, truth.carriage_mm, screw_pitch_mm_, truth.force_N);
  const EffectSlot& mains = (*effects_)[EffectKind::kMainsInterference];
  if (mains.on) force += forms::mains_N(mains, truth.time_s, truth.carriage_velocity_mm_s);
  return force;
}

void SensorChain::advance(double dt_s) {
  const EffectSlot& drift = (*effects_)[EffectKind::kSensorDrift];
  if (!drift.on || drift.form != 1) return;
  // Brownian offset: 1.5 mN/sqrt(s) at size 1.
  random_walk_N_ += effects_->effect_rng().gaussian(0.0015 * drift.size * std::sqrt(dt_s));
}

double SensorChain::quantise(double volts) const {
  return std::round(volts / p_.adc_lsb_V) * p_.adc_lsb_V;
}

drivers::AnalogFrame SensorChain::convert(const TrueSignals& truth, RandomSource& rng) const {
  drivers::AnalogFrame frame;
  const double force = instrument_force_N(truth) + rng.gaussian(p_.force_noise_N);
  frame.force_volts = quantise(p_.force_offset_V + p_.force_gain_V_per_N * force);
  const double position = truth.carriage_mm + rng.gaussian(p_.position_noise_mm);
  frame.position_volts = quantise(p_.position_offset_V + p_.position_gain_V_per_mm * position);
  const double iop = truth.iop_mmHg + rng.gaussian(p_.iop_noise_mmHg);
  frame.iop_volts = quantise(p_.iop_offset_V + p_.iop_gain_V_per_mmHg * iop);
  return frame;
}

}  // namespace rig::sim
