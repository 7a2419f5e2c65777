#pragma once
// Ground-truth force between keratome and cornea. Depth is measured from the corneal
// surface along the keratome axis [mm], positive into the eye; force is the axial force on
// the keratome [N], positive pushing into the eye (run-CSV convention).
#include <memory>

#include "rig/sim/active_effects.hpp"
#include "rig/sim/extra_force.hpp"
#include "rig/sim/physics_params.hpp"
#include "rig/sim/random_source.hpp"

namespace rig::sim {

struct TissueInput {
  double carriage_depth_mm = 0.0;  // carriage position - surface position
  double velocity_mm_s = 0.0;      // carriage velocity (+ into the eye)
  double iop_mmHg = 15.0;          // current line pressure
  double dt_s = 1e-4;
  double run_time_s = 0.0;  // since the eye was mounted
};

class TissueTruth {
 public:
  TissueTruth(const TissueParams& params, const ActiveEffects& effects)
      : p_(params), effects_(&effects) {}

  void new_eye(RandomSource& rng);                             // a fresh, intact cornea
  double update(const TissueInput& input, RandomSource& rng);  // returns force [N]

  double force_N() const { return force_N_; }
  double tip_depth_mm() const { return tip_mm_; }
  bool punctured() const { return punctured_; }
  // Puncture and final depth for an IOP (Table 1, linear in IOP, clamped at the ends) [mm].
  double puncture_depth_mm(double iop_mmHg) const;
  double final_depth_mm(double iop_mmHg) const;
  // This eye's draw (1 and 0 when eyes do not vary).
  double eye_stiffness() const { return eye_stiffness_; }
  double eye_puncture_shift_mm() const { return eye_xpi_shift_mm_; }
  // A force law from outside the catalogue (the effect zoo), or nullptr.
  void set_extra_force(std::shared_ptr<const ExtraForce> law) { extra_ = std::move(law); }

 private:
  double elastic_force(double tip_mm, double iop_mmHg) const;
  double cutting_force(double tip_mm, double iop_mmHg) const;
  double force_at(double tip_mm, double iop_mmHg) const;
  double scaled_by_effects(double force, double tip_mm) const;
  double friction_force(double tip_mm, double velocity_mm_s) const;
  double solve_tip(const TissueInput& input) const;
  void track_motion(const TissueInput& input, RandomSource& rng);
  void track_relaxation(bool held, double advanced_mm, double dt_s);
  void track_tearing();
  double tearing_force(double tip_mm) const;
  double extra_force(const TissueInput& input, double tissue_force_N) const;

  TissueParams p_;
  const ActiveEffects* effects_;
  bool punctured_ = false;
  double front_mm_ = 0.0;  // deepest tip depth reached
  double tip_mm_ = -1.0;
  double force_N_ = 0.0;
  double advance_velocity_mm_s_ = 2.0;  // smoothed velocity of the last advance
  double hold_s_ = 0.0;                 // time at rest at the front
  double hold_front_mm_ = 0.0;          // the front when the current hold began [mm]
  double tear_N_ = 0.0;                 // AR(1) tearing fluctuation
  double eye_stiffness_ = 1.0;          // per-eye variability factor
  double eye_xpi_shift_mm_ = 0.0;
  double eye_cutting_ = 1.0;
  double punctured_at_mm_ = 0.0;  // where the blade entered
  double tear_cycles_ = 0.0;      // periodic tearing: tears completed since the puncture
  double relaxed_ = 0.0;          // relaxed fraction of the tissue force (stress_relaxation)
  double relaxed_at_hold_start_ = 0.0;
  double friction_state_N_per_mm_ = 0.0;  // LuGre / Dahl friction state per inserted length
  double tear_from_mm_ = 0.0;             // aperiodic tearing: the current tear's start and end
  double tear_to_mm_ = 0.0;
  std::shared_ptr<const ExtraForce> extra_;
};

}  // namespace rig::sim
