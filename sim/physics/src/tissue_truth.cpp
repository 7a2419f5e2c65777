#include "rig/sim/tissue_truth.hpp"

#include <algorithm>
#include <cmath>

#include "rig/sim/effect_forms.hpp"

namespace rig::sim {
namespace {

constexpr double kReferenceVelocity_mm_s = 2.0;
constexpr double kRelaxRecovery_mm = 0.15;  // advancing this far replaces relaxed tissue by fresh
constexpr double kTearSpacing_mm = 0.35;    // mean spacing of aperiodic tears
constexpr double kHoldTolerance_mm =
    0.05;  // how far a held blade may settle without ending the hold

double interpolate(const double* xs, const double* ys, int n, double x) {
  if (x <= xs[0]) return ys[0];
  for (int i = 1; i < n; ++i) {
    if (x <= xs[i]) return ys[i - 1] + (ys[i] - ys[i - 1]) * (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
  }
  return ys[n - 1];
}

}  // namespace

void TissueTruth::new_eye(RandomSource& rng) {
  punctured_ = false;
  front_mm_ = 0.0;
  tip_mm_ = -1.0;
  force_N_ = 0.0;
  advance_velocity_mm_s_ = kReferenceVelocity_mm_s;
  hold_s_ = 0.0;
  hold_front_mm_ = 0.0;
  tear_N_ = 0.0;
  relaxed_ = relaxed_at_hold_start_ = 0.0;
  friction_state_N_per_mm_ = 0.0;
  // Always three draws, so the noise stream does not depend on eye_variability.
  const double spread = p_.eye_variability;
  eye_stiffness_ = std::max(0.3, 1.0 + rng.gaussian(p_.eye_stiffness_sigma * spread));
  eye_xpi_shift_mm_ = rng.gaussian(p_.eye_puncture_sigma_mm * spread);
  eye_cutting_ = std::max(0.3, 1.0 + rng.gaussian(p_.eye_cutting_sigma * spread));
}

double TissueTruth::puncture_depth_mm(double iop_mmHg) const {
  double shift = eye_xpi_shift_mm_;
  const EffectSlot& cov = (*effects_)[EffectKind::kCovariate];
  if (cov.on) shift += forms::covariate_change(cov, effects_->covariate_value()).puncture_shift_mm;
  return interpolate(p_.table_iop_mmHg, p_.table_xpi_mm, 4, iop_mmHg) + shift;
}

double TissueTruth::final_depth_mm(double iop_mmHg) const {
  return interpolate(p_.table_iop_mmHg, p_.table_xpf_mm, 4, iop_mmHg);
}

double TissueTruth::elastic_force(double tip_mm, double iop_mmHg) const {
  if (tip_mm <= 0.0) return 0.0;
  double scale = eye_stiffness_;
  double toe_end = p_.toe_end_mm;
  const EffectSlot& iop = (*effects_)[EffectKind::kIopStiffness];
  if (iop.on) {
    const forms::IopChange change = forms::iop_change(iop, iop_mmHg);
    scale *= change.stiffness_factor;
    toe_end *= change.toe_factor;
  }
  const EffectSlot& cov = (*effects_)[EffectKind::kCovariate];
  if (cov.on) scale *= forms::covariate_change(cov, effects_->covariate_value()).precut_factor;
  const double toe = p_.toe_slope_N_per_mm * scale;
  if (tip_mm <= toe_end) return toe * tip_mm;
  return toe * toe_end + p_.precut_slope_N_per_mm * scale * (tip_mm - toe_end);
}

double TissueTruth::cutting_force(double tip_mm, double iop_mmHg) const {
  const double xpi = puncture_depth_mm(iop_mmHg);
  const double xpf = final_depth_mm(iop_mmHg);
  const double xc = std::min(p_.cut_end_mm, xpf - 1e-3);
  double cutting_scale = eye_cutting_;
  const EffectSlot& cov = (*effects_)[EffectKind::kCovariate];
  if (cov.on)
    cutting_scale *= forms::covariate_change(cov, effects_->covariate_value()).cutting_factor;
  auto plateau = [&](double x) {
    const double arg = std::max(x - p_.cut_log_origin_mm, 1e-3);
    return cutting_scale * (p_.cut_log_gain_N * (std::log(arg) - p_.cut_linear_per_mm * x) +
                            p_.cut_iop_gain_N_per_mmHg * iop_mmHg + p_.cut_offset_N);
  };
  if (tip_mm < xpi + p_.drop_width_mm) {
    const double peak = elastic_force(xpi, iop_mmHg);
    const double end = plateau(xpi + p_.drop_width_mm);
    return peak + (end - peak) * std::clamp((tip_mm - xpi) / p_.drop_width_mm, 0.0, 1.0);
  }
  if (tip_mm < xc) return plateau(tip_mm);
  if (tip_mm < xpf) return plateau(xc) * (xpf - tip_mm) / (xpf - xc);
  return 0.0;
}

double TissueTruth::tearing_force(double tip_mm) const {
  const EffectSlot& stick = (*effects_)[EffectKind::kStickSlip];
  const bool cutting =
      punctured_ && tip_mm > punctured_at_mm_ + p_.drop_width_mm && tip_mm < p_.cut_end_mm;
  // A held blade keeps the tear it has built up; servo jitter of micrometres backwards does
  // not let it go (until 2026-11-28 1 um did, and the force stepped mid-hold); withdrawing does.
  if (!stick.on || !cutting || tip_mm < front_mm_ - kHoldTolerance_mm) return 0.0;
  const double amplitude = forms::tearing_amplitude_N(stick, advance_velocity_mm_s_);
  if (stick.form != 0)
    return amplitude * forms::tearing_pattern(stick, tip_mm - punctured_at_mm_, tear_cycles_);
  // Aperiodic: each tear builds up over its own length, then lets go.
  const double length = std::max(tear_to_mm_ - tear_from_mm_, 1e-6);
  return amplitude * (2.0 * std::clamp((tip_mm - tear_from_mm_) / length, 0.0, 1.0) - 1.0);
}

double TissueTruth::scaled_by_effects(double force, double tip_mm) const {
  const EffectSlot& rate = (*effects_)[EffectKind::kRateDependence];
  if (rate.on) force *= forms::rate_factor(rate, advance_velocity_mm_s_, punctured_);
  if ((*effects_)[EffectKind::kStressRelaxation].on) force *= 1.0 - relaxed_;
  return force + tearing_force(tip_mm);
}

double TissueTruth::friction_force(double tip_mm, double velocity_mm_s) const {
  const EffectSlot& friction = (*effects_)[EffectKind::kShaftFriction];
  if (!friction.on || !punctured_) return 0.0;
  const double inserted_mm = std::max(0.0, std::min(tip_mm, front_mm_) - punctured_at_mm_);
  if (friction.form != 0) return friction_state_N_per_mm_ * inserted_mm;  // LuGre and Dahl: a state
  return forms::friction_per_mm(friction, velocity_mm_s) * inserted_mm;
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

// The tip where the mount's lag matches the force it carries: tip = carriage - lag(F(tip)).
// Solved by bisection: behind the cut front the force falls within release_width_mm, so a
// stiff tissue on a soft mount is a loop gain of 10-30, and the damped fixed-point iteration
// used until 2026-11-28 oscillated; its last iterate could put the tip (and the front) ahead
// of the blade's balance, and the tissue then carried no force for millimetres after a stop
// (draws 180047 and 180055: 0 N from 6 to 8 mm in 4-5 of 9 runs).
double TissueTruth::solve_tip(const TissueInput& input) const {
  const EffectSlot& compliance = (*effects_)[EffectKind::kRigCompliance];
  const double carriage = input.carriage_depth_mm;
  if (!compliance.on || compliance.size <= 0.0 || carriage <= 0.0) return carriage;
  // gap(tip) = carriage - lag(F(tip)) - tip: negative at the carriage, positive at the
  // surface (no force, no lag), so a balance lies between.
  auto gap = [&](double tip) {
    const double force = force_at(tip, input.iop_mmHg) + friction_force(tip, input.velocity_mm_s);
    return carriage - forms::compliance_lag_mm(compliance, force) - tip;
  };
  if (gap(carriage) >= 0.0) return carriage;
  double ahead = carriage;
  double behind =
      carriage - forms::compliance_lag_mm(compliance, force_N_);  // near last step's balance
  if (behind >= ahead || gap(behind) < 0.0) behind = 0.0;
  for (int i = 0; i < 40 && ahead - behind > 1e-7; ++i) {  // to 0.1 um
    const double mid = 0.5 * (ahead + behind);
    (gap(mid) < 0.0 ? ahead : behind) = mid;
  }
  return behind;
}

void TissueTruth::track_relaxation(bool held, double advanced_mm, double dt_s) {
  const EffectSlot& relax = (*effects_)[EffectKind::kStressRelaxation];
  if (held) {
    if (hold_s_ <= 0.0) relaxed_at_hold_start_ = relaxed_;
    hold_s_ += dt_s;
    if (relax.on)
      relaxed_ =
          1.0 - (1.0 - relaxed_at_hold_start_) * (1.0 - forms::relaxed_fraction(relax, hold_s_));
  } else if (advanced_mm > 0.0) {
    hold_s_ = 0.0;
    relaxed_ *= std::exp(-advanced_mm / kRelaxRecovery_mm);  // fresh tissue carries the load again
  }
}

void TissueTruth::track_tearing() {
  const EffectSlot& stick = (*effects_)[EffectKind::kStickSlip];
  if (!stick.on || stick.form != 0 || !punctured_) return;
  while (front_mm_ >= tear_to_mm_) {
    tear_from_mm_ = std::max(tear_to_mm_, punctured_at_mm_);
    tear_to_mm_ = tear_from_mm_ + kTearSpacing_mm * effects_->effect_rng().uniform(0.4, 1.6);
  }
}

void TissueTruth::track_motion(const TissueInput& input, RandomSource& rng) {
  const double tip = tip_mm_;
  if (input.velocity_mm_s > 0.1) {
    advance_velocity_mm_s_ +=
        (input.velocity_mm_s - advance_velocity_mm_s_) * std::min(1.0, input.dt_s / 0.02);
  }
  // Held: the blade neither advances past where the hold began nor withdraws from its deepest
  // point by more than 50 um. Servo jitter of a few um does not end a hold, in either
  // direction: a slow run's servo settles forward by ~4 um over a 2 s stop, and until
  // 2026-11-28 each um of that creep ended the hold and restarted the relaxation spectrum
  // from t = 0, so slow runs relaxed twice as far in the same stop (draw 80031: to 35 % of
  // the force at 0.6 mm/s, 64 % at 1.3 mm/s, with one relaxation law).
  // The tissue stays relaxed while the blade is withdrawn; only a new advance reloads it.
  // Creep is slower than 0.05 mm/s (10x below the slowest cut): a cut goes on cutting.
  constexpr double kCreepSpeed_mm_s = 0.05;
  const bool at_front = tip > 0.0 && tip <= front_mm_ && tip >= front_mm_ - kHoldTolerance_mm;
  const bool creeping = hold_s_ > 0.0 && tip > front_mm_ &&
                        tip <= hold_front_mm_ + kHoldTolerance_mm &&
                        std::abs(input.velocity_mm_s) < kCreepSpeed_mm_s;
  const bool held = at_front || creeping;
  if (held && hold_s_ <= 0.0) hold_front_mm_ = front_mm_;
  track_relaxation(held, tip - front_mm_, input.dt_s);
  if (tip > front_mm_) {
    const double advanced = tip - front_mm_;
    front_mm_ = tip;
    if (punctured_) tear_cycles_ += advanced * forms::tearing_cycles_per_mm(advance_velocity_mm_s_);
    if (punctured_ && p_.tear_noise_N > 0.0) {
      const double rho = std::exp(-advanced / p_.tear_correlation_mm);
      tear_N_ = rho * tear_N_ + std::sqrt(1.0 - rho * rho) * rng.gaussian(p_.tear_noise_N);
    }
    if (!punctured_ && tip >= puncture_depth_mm(input.iop_mmHg)) {
      punctured_ = true;
      punctured_at_mm_ = tip;
      tear_cycles_ = 0.0;
      tear_from_mm_ = tear_to_mm_ = tip;
    }
  }
  track_tearing();
}

double TissueTruth::extra_force(const TissueInput& input, double tissue_force_N) const {
  if (!extra_) return 0.0;
  ForceContext c;
  c.run_time_s = input.run_time_s;
  c.tip_mm = tip_mm_;
  c.front_mm = front_mm_;
  c.velocity_mm_s = input.velocity_mm_s;
  c.tissue_force_N = tissue_force_N;
  c.iop_mmHg = input.iop_mmHg;
  c.hold_s = hold_s_;
  c.punctured_at_mm = punctured_at_mm_;
  c.punctured = punctured_;
  return extra_->force_N(c);
}

double TissueTruth::update(const TissueInput& input, RandomSource& rng) {
  const double previous_tip = tip_mm_;
  tip_mm_ = solve_tip(input);
  track_motion(input, rng);
  const EffectSlot& friction = (*effects_)[EffectKind::kShaftFriction];
  if (friction.on && friction.form != 0 && punctured_ && previous_tip > -1.0) {
    const double dx_mm = tip_mm_ - previous_tip;
    friction_state_N_per_mm_ += friction.form == 1
                                    ? forms::lugre_step(friction, friction_state_N_per_mm_, dx_mm,
                                                        std::abs(input.velocity_mm_s))
                                    : forms::dahl_step(friction, friction_state_N_per_mm_, dx_mm);
  }
  const double tissue =
      force_at(tip_mm_, input.iop_mmHg) + friction_force(tip_mm_, input.velocity_mm_s);
  force_N_ = tissue + extra_force(input, tissue);
  return force_N_;
}

}  // namespace rig::sim
