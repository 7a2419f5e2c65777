#include "rig/sim/effect_forms.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rig::sim::forms {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kReferenceVelocity_mm_s = 2.0;
constexpr double kReferenceIop_mmHg = 15.0;
constexpr double kCovariateReference = 2.0;
constexpr double kPresliding_mm =
    0.1;  // LuGre: the blade's travel over which tissue grip builds to the static level

double sawtooth(double cycles) {
  return 2.0 * (cycles - std::floor(cycles)) - 1.0;
}
double logistic(double z) {
  return 1.0 / (1.0 + std::exp(-z));
}

// Carreau shear thinning: viscous stress ~ v (1 + (lambda v)^2)^((n-1)/2), lambda 1 s/mm, n 0.3.
double carreau_stress(double v) {
  return v * std::pow(1.0 + v * v, -0.35);
}

}  // namespace

double rate_factor(const EffectSlot& slot, double v, bool after_puncture) {
  v = std::max(v, 0.05);
  const double size = slot.size;
  switch (slot.form) {
    case 0:  // carreau, cutting only
      if (!after_puncture) return 1.0;
      return std::max(
          0.1,
          1.0 + 0.45 * size * (carreau_stress(v) / carreau_stress(kReferenceVelocity_mm_s) - 1.0));
    case 1:  // power law with a cutoff: no rate effect below 1.5 mm/s
      return std::pow(std::max(v, 1.5) / kReferenceVelocity_mm_s, 0.35 * size);
    case 2:  // logarithmic at speed, linear when slow (Eyring: asinh(v / 0.6 mm/s))
      return std::max(
          0.1, 1.0 + 0.3 * size *
                         (std::asinh(v / 0.6) / std::asinh(kReferenceVelocity_mm_s / 0.6) - 1.0));
    default: {  // exponential saturation: the rate stiffening levels off past ~1.2 mm/s
      const auto rise = [](double speed) { return 1.0 - std::exp(-speed / 1.2); };
      return std::max(0.1, 1.0 + 0.3 * size * (rise(v) / rise(kReferenceVelocity_mm_s) - 1.0));
    }
  }
}

IopChange iop_change(const EffectSlot& slot, double iop_mmHg) {
  const double dp = iop_mmHg - kReferenceIop_mmHg;
  IopChange change;
  switch (slot.form) {
    case 0:  // saturating, exponentially: the stiffening levels off above ~18 mmHg
      change.stiffness_factor = std::max(0.1, 1.0 + 0.35 * slot.size * -std::expm1(-dp / 1.5));
      break;
    case 1:  // pre-stress: the slack toe region shortens, the slope barely changes
      change.toe_factor = std::clamp(1.0 - 0.25 * slot.size * dp, 0.1, 2.0);
      change.stiffness_factor = 1.0 + 0.02 * slot.size * dp;
      break;
    default: {  // fibre recruitment: no change below ~16 mmHg, then +12 % per mmHg (a smooth hinge)
      const double over = dp - 1.0;
      change.stiffness_factor = 1.0 + 0.12 * slot.size * 0.3 * std::log1p(std::exp(over / 0.3));
      break;
    }
  }
  return change;
}

double friction_per_mm(const EffectSlot& slot, double v) {
  const double size = slot.size;
  const double speed = std::abs(v);
  if (slot.form ==
      0) {  // Coulomb + a lubricating film's drag growing as sqrt(v), per inserted length
    return size * (0.004 + 0.003 * std::sqrt(speed)) * std::tanh(v / 0.05);
  }
  return stribeck_curve_per_mm(slot, speed) * std::tanh(v / 0.02);
}

double stribeck_curve_per_mm(const EffectSlot& slot, double speed_mm_s) {
  // Static 0.009, Coulomb 0.004 N/mm, Stribeck speed 0.7 mm/s, + viscous 0.0005 N/mm per mm/s
  const double stribeck = 0.004 + 0.005 * std::exp(-(speed_mm_s / 0.7) * (speed_mm_s / 0.7));
  return slot.size * (stribeck + 0.0005 * speed_mm_s);
}

double lugre_step(const EffectSlot& slot, double z_N_per_mm, double dx_mm, double speed_mm_s) {
  // LuGre (Canudas de Wit et al. 1995) without bristle damping, per inserted length: the
  // bristles (here the tissue gripping the shaft) deflect with the blade, dz/dx = sigma0 (1 -
  // z sgn(dx) / g(v)), so a stop keeps the load and a reversal of a few µm moves z by
  // sigma0 per mm, not by a full flip. sigma0 lets the static level build over kPresliding_mm.
  const double g = stribeck_curve_per_mm(slot, speed_mm_s);
  if (g <= 0.0 || dx_mm == 0.0) return 0.0;
  const double sigma0 = stribeck_curve_per_mm(slot, 0.0) / kPresliding_mm;
  const double direction = dx_mm > 0.0 ? 1.0 : -1.0;
  return sigma0 * (1.0 - z_N_per_mm * direction / g) * dx_mm;
}

double dahl_step(const EffectSlot& slot, double z, double dx_mm) {
  // dz/dx = sigma (1 - z/mu sgn(dx)); mu 0.006 N/mm, the state settles within ~0.3 mm.
  const double mu = 0.006 * slot.size;
  if (mu <= 0.0) return 0.0;
  const double sigma = mu / 0.3;
  const double direction = dx_mm > 0.0 ? 1.0 : (dx_mm < 0.0 ? -1.0 : 0.0);
  return sigma * (1.0 - z / mu * direction) * dx_mm;
}

double compliance_lag_mm(const EffectSlot& slot, double force_N) {
  const double f = std::max(force_N, 0.0);
  const double size = slot.size;
  switch (slot.form) {
    case 0:  // hardening mount: 1.5/size N/mm at small loads, against a stop at 0.06 size mm
      return 0.06 * size * std::tanh(f / 0.09);
    case 1:  // softening mount: k = 3 N/mm / (1 + (F / 0.15 N)^2)
      return f / 3.0 * size * (1.0 + (f / 0.15) * (f / 0.15));
    case 2:  // backlash: a 0.04 mm gap closes at ~10 mN, then a stiff 6 N/mm mount
      return 0.04 * size * std::tanh(f / 0.01) + f / 6.0;
    default:  // exponential stiffening: k = 0.9/size exp(F / 0.15 N) N/mm, lag = integral dF / k
      return 0.15 * size / 0.9 * -std::expm1(-f / 0.15);
  }
}

double relaxed_fraction(const EffectSlot& slot, double t) {
  if (t <= 0.0) return 0.0;
  const double size = slot.size;
  double fraction = 0.0;
  switch (slot.form) {
    case 0: {  // Fung's quasi-linear viscoelasticity: a box spectrum from 0.05 s to 20 s, C 0.08
      const auto e1 = [](double x) { return -std::expint(-x); };  // the exponential integral E1
      const double c = 0.08 * size, tau1 = 0.05, tau2 = 20.0;
      return std::clamp(
          1.0 - (1.0 + c * (e1(t / tau2) - e1(t / tau1))) / (1.0 + c * std::log(tau2 / tau1)), 0.0,
          0.9);
    }
    case 1:  // three-term Prony series: 0.1 s, 1 s, 8 s
      fraction = 0.1 * (1.0 - std::exp(-t / 0.1)) + 0.12 * (1.0 - std::exp(-t)) +
                 0.15 * (1.0 - std::exp(-t / 8.0));
      break;
    default: {  // fractional Zener: Mittag-Leffler E_1/2(-(t/0.5 s)^1/2) = exp(z^2) erfc(z), 30 %
      const double z = std::sqrt(t / 0.5);
      // Past z = 5 (12.5 s) exp(z^2) overflows where erfc underflows: the asymptote instead.
      const double remaining = z < 5.0 ? std::exp(z * z) * std::erfc(z)
                                       : (1.0 - 0.5 / (z * z)) / (z * std::sqrt(std::numbers::pi));
      return std::min(0.9, 0.3 * size * (1.0 - remaining));
    }
  }
  return std::min(0.9, size * fraction);
}

CovariateChange covariate_change(const EffectSlot& slot, double value) {
  const double dh = value - kCovariateReference;
  CovariateChange change;
  switch (slot.form) {
    case 0:  // sigmoid softening of the cut after ~2 units (post-mortem hours)
      change.cutting_factor = 1.0 - 0.3 * slot.size * (logistic(dh / 0.5) - 0.5);
      break;
    case 1:  // hinge on every phase: no change below 1.5, then -10 % per unit
      change.precut_factor = change.cutting_factor =
          std::max(0.1, 1.0 - 0.1 * slot.size * std::max(0.0, value - 1.5));
      break;
    default:  // the puncture moves deeper: softer tissue yields later, levelling off
      change.puncture_shift_mm = 0.25 * slot.size * std::tanh(dh / 1.5);
      break;
  }
  return change;
}

double tearing_pattern(const EffectSlot& slot, double past_mm, double tear_cycles) {
  if (slot.form == 1) {  // period grows with depth: 0.25 mm (1 + 0.25/mm past the puncture)
    const double growth = 0.25;
    return std::sin(kTwoPi * std::log1p(growth * past_mm) / (growth * 0.25) + slot.phase_rad);
  }
  return sawtooth(tear_cycles);  // velocity weakening: build-and-release
}

// Velocity weakening: a tear is as long as the speed it was cut at makes it. Until
// 2026-11-28 the pattern was sawtooth(past / period(v now)): each percent of servo speed
// ripple then moved the tenth tear by a tenth of a cycle, a jitter no tearing has.
// A tear's length grows linearly with the speed, 0.35 mm at 2 mm/s (0.2 mm + 0.075 s v).
double tearing_cycles_per_mm(double v) {
  return 1.0 / (0.2 + 0.075 * std::max(v, 0.1));
}

double tearing_amplitude_N(const EffectSlot& slot, double v) {
  const double amplitude = 0.006 * slot.size;
  if (slot.form != 2) return amplitude;
  return amplitude *
         std::pow(kReferenceVelocity_mm_s / std::max(v, 0.1), 0.7);  // stronger when slow
}

double drift_N(const EffectSlot& slot, double t, double random_walk_N) {
  const double size = slot.size * slot.run_factor;
  switch (slot.form) {
    case 0: {  // thermal first-order, time constant drawn per run (2-20 s)
      const double tau = 2.0 + 18.0 * slot.run_values[0];
      return 0.012 * size * (1.0 - std::exp(-t / tau));
    }
    case 1:  // random walk (state kept by the sensor chain)
      return random_walk_N;
    case 2: {  // a step (thermal EMF, connector) at a random time 3-20 s, 20 ms wide
      const double at = 3.0 + 17.0 * slot.run_values[1];
      return 0.008 * size * logistic((t - at) / 0.005);
    }
    default:  // warm-up of the gauge (1 s) against its housing (8 s): two time constants, an
              // overshoot
      return 0.012 * size * (1.0 - 1.6 * std::exp(-t / 1.0) + 0.6 * std::exp(-t / 8.0));
  }
}

double ripple_N(const EffectSlot& slot, double x_mm, double pitch_mm, double force_N) {
  const double amplitude = 0.004 * slot.size;
  const double cycles = x_mm / pitch_mm + slot.phase_rad / kTwoPi;
  switch (slot.form) {
    case 0: {  // lead error: the thread's period stretches 0.15 % per mm along the travel
      const double stretched = cycles + 0.0015 * (x_mm - 20.0) * (x_mm - 20.0) / pitch_mm;
      return amplitude * std::sin(kTwoPi * stretched);
    }
    case 1:  // nut friction ripple grows with the thread load
      return amplitude * (0.3 + std::max(force_N, 0.0) / 0.2) * std::sin(kTwoPi * cycles);
    default:  // sawtooth
      return amplitude * sawtooth(cycles);
  }
}

double mains_N(const EffectSlot& slot, double t, double carriage_velocity_mm_s) {
  const double amplitude = 0.004 * slot.size;
  const double offset_hz = 0.1 * (slot.run_values[2] - 0.5);  // the grid is off by up to 0.05 Hz
  const double base_hz = slot.form == 3 ? 60.0 : 50.0;
  // Slow wander of the grid frequency, +-0.03 Hz over 15 s, integrated into the phase.
  const double wander = -0.03 * 15.0 / kTwoPi * std::cos(kTwoPi * t / 15.0 + slot.phase_rad);
  const double phase = kTwoPi * ((base_hz + offset_hz) * t + wander) + slot.phase_rad;
  switch (slot.form) {
    case 1:  // odd harmonics up to the 5th (rectifier loads)
      return amplitude * (0.7 * std::sin(phase) + 0.35 * std::sin(3.0 * phase + 1.0) +
                          0.25 * std::sin(5.0 * phase + 2.0));
    case 2:  // picked up from the motor drive: only while the carriage moves
      return amplitude * std::min(1.0, std::abs(carriage_velocity_mm_s) / 0.5) * std::sin(phase);
    default:  // drifting 50 Hz, or 60 Hz
      return amplitude * std::sin(phase);
  }
}

}  // namespace rig::sim::forms
