#include "rig/sim/tissue_truth.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rig::sim {
namespace {

// Nominal magnitudes of the hidden effects at size 1 (see docs/sim.md).
constexpr double kRatePower = 0.3;              // F ~ (v / 2 mm/s)^0.3
constexpr double kRateLinearPerMmS = 0.075;     // F ~ 1 + 0.075 (v - 2)
constexpr double kReferenceVelocity_mm_s = 2.0;
constexpr double kIopStiffnessPerMmHg = 0.08;   // pre-cut stiffness per mmHg above 15
constexpr double kReferenceIop_mmHg = 15.0;
constexpr double kFriction_N_per_mm = 0.006;    // along the inserted blade
constexpr double kFrictionSaturation_mm = 3.0;
constexpr double kFrictionSpeed_mm_s = 0.05;    // smoothing of the friction sign
constexpr double kComplianceStiffness_N_per_mm = 1.5;
constexpr double kComplianceStiffening_N = 0.15;
constexpr double kStickSlipAmplitude_N = 0.006;
constexpr double kStickSlipPeriod_mm = 0.35;
constexpr double kRelaxFraction = 0.35;
constexpr double kRelaxTau_s = 0.8;
constexpr double kRelaxPowerTau_s = 0.3;
constexpr double kRelaxPower = 0.15;
constexpr double kCovariatePerUnit = 0.08;      // cutting force change per covariate unit
constexpr double kCovariateReference = 2.0;

double interpolate(const double* xs, const double* ys, int n, double x) {
  if (x <= xs[0]) return ys[0];
  for (int i = 1; i < n; ++i) {
    if (x <= xs[i]) return ys[i - 1] + (ys[i] - ys[i - 1]) * (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
  }
  return ys[n - 1];
}

double periodic(bool sawtooth, double cycles) {
  if (sawtooth) return 2.0 * (cycles - std::floor(cycles)) - 1.0;
  return std::sin(2.0 * std::numbers::pi * cycles);
}

}  // namespace

void TissueTruth::new_eye(RandomSource& rng) {
  punctured_ = false;
  front_mm_ = 0.0;
  tip_mm_ = -1.0;
  force_N_ = 0.0;
  advance_velocity_mm_s_ = kReferenceVelocity_mm_s;
  hold_s_ = 0.0;
  tear_N_ = 0.0;
  eye_stiffness_ = 1.0 + rng.gaussian(p_.eye_variability);
  eye_xpi_shift_mm_ = rng.gaussian(p_.eye_variability * 2.0);
}

double TissueTruth::puncture_depth_mm(double iop_mmHg) const {
  return interpolate(p_.table_iop_mmHg, p_.table_xpi_mm, 4, iop_mmHg) + eye_xpi_shift_mm_;
}

double TissueTruth::final_depth_mm(double iop_mmHg) const {
  return interpolate(p_.table_iop_mmHg, p_.table_xpf_mm, 4, iop_mmHg);
}

double TissueTruth::elastic_force(double tip_mm, double iop_mmHg) const {
  if (tip_mm <= 0.0) return 0.0;
  double scale = eye_stiffness_;
  const EffectSlot& iop = (*effects_)[EffectKind::kIopStiffness];
  if (iop.on) {
    const double k = kIopStiffnessPerMmHg * iop.size * (iop_mmHg - kReferenceIop_mmHg);
    scale *= iop.form == 0 ? std::exp(k) : std::max(0.1, 1.0 + k);
  }
  const double toe = p_.toe_slope_N_per_mm * scale;
  if (tip_mm <= p_.toe_end_mm) return toe * tip_mm;
  return toe * p_.toe_end_mm + p_.precut_slope_N_per_mm * scale * (tip_mm - p_.toe_end_mm);
}

double TissueTruth::cutting_force(double tip_mm, double iop_mmHg) const {
  const double xpi = puncture_depth_mm(iop_mmHg);
  const double xpf = final_depth_mm(iop_mmHg);
  const double xc = std::min(p_.cut_end_mm, xpf - 1e-3);
  auto plateau = [&](double x) {
    const double arg = std::max(x - p_.cut_log_origin_mm, 1e-3);
    return p_.cut_log_gain_N * (std::log(arg) - p_.cut_linear_per_mm * x) +
           p_.cut_iop_gain_N_per_mmHg * iop_mmHg + p_.cut_offset_N;
  };
  double force = 0.0;
  if (tip_mm < xpi + p_.drop_width_mm) {
    const double peak = elastic_force(xpi, iop_mmHg);
    const double end = plateau(xpi + p_.drop_width_mm);
    force = peak + (end - peak) * std::clamp((tip_mm - xpi) / p_.drop_width_mm, 0.0, 1.0);
  } else if (tip_mm < xc) {
    force = plateau(tip_mm);
  } else if (tip_mm < xpf) {
    force = plateau(xc) * (xpf - tip_mm) / (xpf - xc);
  }
  const EffectSlot& cov = (*effects_)[EffectKind::kCovariate];
  if (cov.on) {
    const double k = kCovariatePerUnit * cov.size * (effects_->covariate_value() - kCovariateReference);
    force *= cov.form == 0 ? std::exp(-k) : std::max(0.1, 1.0 - k);
  }
  return force;
}

double TissueTruth::scaled_by_effects(double force, double tip_mm) const {
  const EffectSlot& rate = (*effects_)[EffectKind::kRateDependence];
  if (rate.on) {
    const double v = std::max(advance_velocity_mm_s_, 0.05);
    force *= rate.form == 0
                 ? std::pow(v / kReferenceVelocity_mm_s, kRatePower * rate.size)
                 : std::max(0.1, 1.0 + kRateLinearPerMmS * rate.size * (v - kReferenceVelocity_mm_s));
  }
  const EffectSlot& relax = (*effects_)[EffectKind::kStressRelaxation];
  if (relax.on && hold_s_ > 0.0) {
    force *= relax.form == 0
                 ? 1.0 - kRelaxFraction * relax.size * (1.0 - std::exp(-hold_s_ / kRelaxTau_s))
                 : std::pow(1.0 + hold_s_ / kRelaxPowerTau_s, -kRelaxPower * relax.size);
  }
  const EffectSlot& stick = (*effects_)[EffectKind::kStickSlip];
  if (stick.on && punctured_ && tip_mm > punctured_at_mm_ + p_.drop_width_mm && tip_mm < p_.cut_end_mm &&
      tip_mm >= front_mm_ - 1e-3) {
    // Tearing starts at the puncture: its phase is locked to where the blade entered.
    const double cycles = (tip_mm - punctured_at_mm_) / kStickSlipPeriod_mm;
    force += kStickSlipAmplitude_N * stick.size * periodic(stick.form == 0, cycles);
  }
  return force;
}

double TissueTruth::friction_force(double tip_mm, double velocity_mm_s) const {
  const EffectSlot& friction = (*effects_)[EffectKind::kShaftFriction];
  if (!friction.on || !punctured_) return 0.0;
  const double inserted_mm = std::max(0.0, std::min(tip_mm, front_mm_) - punctured_at_mm_);
  const double mu = kFriction_N_per_mm * friction.size;
  const double magnitude =
      friction.form == 0
          ? mu * inserted_mm
          : mu * kFrictionSaturation_mm * (1.0 - std::exp(-inserted_mm / kFrictionSaturation_mm));
  return magnitude * std::tanh(velocity_mm_s / kFrictionSpeed_mm_s);
}

double TissueTruth::force_at(double tip_mm, double iop_mmHg) const {
  if (tip_mm <= 0.0) return 0.0;
  double force = 0.0;
  if (!punctured_ && tip_mm < puncture_depth_mm(iop_mmHg)) {
    force = elastic_force(tip_mm, iop_mmHg);
  } else {
    // Behind the deepest point the cut edge releases elastically over release_width_mm:
    // a held blade keeps its force, a withdrawn one slides back in its own cut.
    const double behind = std::max(0.0, front_mm_ - tip_mm);
    const double at = std::max(tip_mm, front_mm_);
    force = cutting_force(at, iop_mmHg);
    if (at < p_.cut_end_mm) force += tear_N_;
    force *= std::max(0.0, 1.0 - behind / p_.release_width_mm);
  }
  return scaled_by_effects(force, tip_mm);
}

double TissueTruth::solve_tip(const TissueInput& input) const {
  const EffectSlot& compliance = (*effects_)[EffectKind::kRigCompliance];
  if (!compliance.on || compliance.size <= 0.0) return input.carriage_depth_mm;
  double force = force_N_;
  double tip = input.carriage_depth_mm;
  for (int i = 0; i < 6; ++i) {  // fixed point: tip = carriage - F(tip)/k(F)
    const double k = compliance.form == 0
                         ? kComplianceStiffness_N_per_mm / compliance.size
                         : kComplianceStiffness_N_per_mm / compliance.size *
                               (0.6 + std::max(force, 0.0) / kComplianceStiffening_N);
    tip = input.carriage_depth_mm - force / k;
    force = 0.5 * force + 0.5 * (force_at(tip, input.iop_mmHg) +
                                 friction_force(tip, input.velocity_mm_s));
  }
  return tip;
}

void TissueTruth::track_motion(const TissueInput& input, RandomSource& rng) {
  const double tip = tip_mm_;
  if (input.velocity_mm_s > 0.1) {
    advance_velocity_mm_s_ += (input.velocity_mm_s - advance_velocity_mm_s_) * std::min(1.0, input.dt_s / 0.02);
  }
  // Held: the blade neither advances past its deepest point nor withdraws from it by more
  // than 50 um (servo jitter of a few um does not end a hold).
  // The tissue stays relaxed while the blade is withdrawn; only a new advance reloads it.
  const bool held = tip > 0.0 && tip <= front_mm_ && tip >= front_mm_ - 0.05;
  if (held) {
    hold_s_ += input.dt_s;
  } else if (tip > front_mm_) {
    hold_s_ = 0.0;
  }
  if (tip > front_mm_) {
    const double advanced = tip - front_mm_;
    front_mm_ = tip;
    if (punctured_ && p_.tear_noise_N > 0.0) {
      const double rho = std::exp(-advanced / p_.tear_correlation_mm);
      tear_N_ = rho * tear_N_ + std::sqrt(1.0 - rho * rho) * rng.gaussian(p_.tear_noise_N);
    }
    if (!punctured_ && tip >= puncture_depth_mm(input.iop_mmHg)) {
      punctured_ = true;
      punctured_at_mm_ = tip;
    }
  }
}

double TissueTruth::update(const TissueInput& input, RandomSource& rng) {
  tip_mm_ = solve_tip(input);
  track_motion(input, rng);
  force_N_ = force_at(tip_mm_, input.iop_mmHg) + friction_force(tip_mm_, input.velocity_mm_s);
  return force_N_;
}

}  // namespace rig::sim
