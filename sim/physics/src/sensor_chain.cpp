#include "rig/sim/sensor_chain.hpp"

#include <cmath>
#include <numbers>

namespace rig::sim {
namespace {

constexpr double kDriftRate_N_per_s = 0.002;    // linear drift at size 1 (x per-run factor)
constexpr double kDriftWarmup_N = 0.012;        // warm-up step at size 1
constexpr double kDriftWarmupTau_s = 4.0;
constexpr double kRippleAmplitude_N = 0.004;
constexpr double kMainsAmplitude_N = 0.004;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

double sawtooth(double cycles) { return 2.0 * (cycles - std::floor(cycles)) - 1.0; }

}  // namespace

double SensorChain::instrument_force_N(const TrueSignals& truth) const {
  double force = truth.force_N;
  const EffectSlot& drift = (*effects_)[EffectKind::kSensorDrift];
  if (drift.on) {
    force += drift.form == 0
                 ? kDriftRate_N_per_s * drift.size * drift.run_factor * truth.run_time_s
                 : kDriftWarmup_N * drift.size * drift.run_factor *
                       (1.0 - std::exp(-truth.run_time_s / kDriftWarmupTau_s));
  }
  const EffectSlot& ripple = (*effects_)[EffectKind::kSpatialRipple];
  if (ripple.on) {
    const double cycles = truth.carriage_mm / screw_pitch_mm_ + ripple.phase_rad / kTwoPi;
    force += kRippleAmplitude_N * ripple.size *
             (ripple.form == 0 ? std::sin(kTwoPi * cycles) : sawtooth(cycles));
  }
  const EffectSlot& mains = (*effects_)[EffectKind::kMainsInterference];
  if (mains.on) {
    const double hz = mains.form == 2 ? 60.0 : 50.0;
    const double phase = kTwoPi * hz * truth.time_s + mains.phase_rad;
    double wave = std::sin(phase);
    if (mains.form == 1) wave = 0.75 * wave + 0.4 * std::sin(3.0 * phase + 1.0);
    force += kMainsAmplitude_N * mains.size * wave;
  }
  return force;
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
