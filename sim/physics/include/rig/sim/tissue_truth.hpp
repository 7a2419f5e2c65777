#pragma once
// Ground-truth force between keratome and cornea. Depth is measured from the corneal
// surface along the keratome axis [mm], positive into the eye; force is the axial force on
// the keratome [N], positive pushing into the eye (run-CSV convention).
#include "rig/sim/active_effects.hpp"
#include "rig/sim/physics_params.hpp"
#include "rig/sim/random_source.hpp"

namespace rig::sim {

struct TissueInput {
  double carriage_depth_mm = 0.0;  // carriage position - surface position
  double velocity_mm_s = 0.0;      // carriage velocity (+ into the eye)
  double iop_mmHg = 15.0;          // current line pressure
  double dt_s = 1e-4;
};

class TissueTruth {
 public:
  TissueTruth(const TissueParams& params, const ActiveEffects& effects)
      : p_(params), effects_(&effects) {}

  void new_eye(RandomSource& rng);  // a fresh, intact cornea
  double update(const TissueInput& input, RandomSource& rng);  // returns force [N]

  double force_N() const { return force_N_; }
  double tip_depth_mm() const { return tip_mm_; }
  bool punctured() const { return punctured_; }
  // Puncture and final depth for an IOP (Table 1, linear in IOP, clamped at the ends) [mm].
  double puncture_depth_mm(double iop_mmHg) const;
  double final_depth_mm(double iop_mmHg) const;

 private:
  double elastic_force(double tip_mm, double iop_mmHg) const;
  double cutting_force(double tip_mm, double iop_mmHg) const;
  double force_at(double tip_mm, double iop_mmHg) const;
  double scaled_by_effects(double force, double tip_mm) const;
  double friction_force(double tip_mm, double velocity_mm_s) const;
  double solve_tip(const TissueInput& input) const;
  void track_motion(const TissueInput& input, RandomSource& rng);

  TissueParams p_;
  const ActiveEffects* effects_;
  bool punctured_ = false;
  double front_mm_ = 0.0;           // deepest tip depth reached
  double tip_mm_ = -1.0;
  double force_N_ = 0.0;
  double advance_velocity_mm_s_ = 2.0;  // smoothed velocity of the last advance
  double hold_s_ = 0.0;             // time at rest at the front
  double tear_N_ = 0.0;             // AR(1) tearing fluctuation
  double eye_stiffness_ = 1.0;      // per-eye variability factor
  double eye_xpi_shift_mm_ = 0.0;
  double punctured_at_mm_ = 0.0;   // where the blade entered
};

}  // namespace rig::sim
