#pragma once
// The laws of the hidden effects, one function per family, each taking the form index of
// effect_forms(kind) (docs/sim.md has the table with formulas). None of these forms is the
// model lab's own term for the family: the simulator must not be the lab's mirror.
// Sizes are multiples of the nominal magnitude; forces in N, depths in mm, times in s.
#include "rig/sim/active_effects.hpp"

namespace rig::sim::forms {

// Factor on the tissue force for the advance velocity v [mm/s]; `after_puncture` because
// the Carreau form is a viscous cutting resistance that leaves the elastic rise alone.
double rate_factor(const EffectSlot& slot, double v_mm_s, bool after_puncture);

// Pre-cut stiffness: factor on the slopes and the shortened toe length for IOP [mmHg].
struct IopChange {
  double stiffness_factor = 1.0;
  double toe_factor = 1.0;
};
IopChange iop_change(const EffectSlot& slot, double iop_mmHg);

// Friction per inserted length [N/mm] in steady sliding, signed by the velocity: the
// Coulomb + film-drag form as the simulator runs it; the Stribeck form's curve (the simulator
// runs that one as LuGre's state, lugre_step).
double friction_per_mm(const EffectSlot& slot, double velocity_mm_s);
// The Stribeck curve g(|v|) [N/mm]: the friction per inserted length in steady sliding.
double stribeck_curve_per_mm(const EffectSlot& slot, double speed_mm_s);
// LuGre's bristle law: the change of the friction state z [N/mm] over a displacement dx [mm].
double lugre_step(const EffectSlot& slot, double z_N_per_mm, double dx_mm, double speed_mm_s);
// Dahl's law: the change of the friction state z [N/mm] over a displacement dx [mm].
double dahl_step(const EffectSlot& slot, double z_N_per_mm, double dx_mm);

// How far the tip lags the carriage under the axial force [mm].
double compliance_lag_mm(const EffectSlot& slot, double force_N);

// Relaxed fraction of the force after `hold_s` at rest (0 = none).
double relaxed_fraction(const EffectSlot& slot, double hold_s);

// Factor on the cutting force and the shift of the puncture depth for a covariate value.
struct CovariateChange {
  double precut_factor = 1.0;
  double cutting_factor = 1.0;
  double puncture_shift_mm = 0.0;
};
CovariateChange covariate_change(const EffectSlot& slot, double value);

// Periodic tearing pattern (-1..1) at `past_puncture_mm` into the cut, `tear_cycles` tears
// completed since the puncture (TissueTruth accumulates tearing_cycles_per_mm over each
// advance); the aperiodic form is drawn by TissueTruth from its tear schedule instead.
double tearing_pattern(const EffectSlot& slot, double past_puncture_mm, double tear_cycles);
// Tears per mm of cut at advance velocity v [mm/s] (the velocity-weakening form's rate).
double tearing_cycles_per_mm(double v_mm_s);
double tearing_amplitude_N(const EffectSlot& slot, double v_mm_s);

// Instrument effects on the force channel [N] (sensor_chain applies them).
double drift_N(const EffectSlot& slot, double run_time_s, double random_walk_N);
double ripple_N(const EffectSlot& slot, double carriage_mm, double screw_pitch_mm, double force_N);
double mains_N(const EffectSlot& slot, double time_s, double carriage_velocity_mm_s);

}  // namespace rig::sim::forms
