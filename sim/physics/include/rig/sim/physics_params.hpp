#pragma once
// Parameters of the simulated rig. Units are in every name or comment; positions are
// carriage coordinates measured from the mechanical home [mm] unless named "depth".
#include <cstdint>

namespace rig::sim {

struct MotorScrewParams {
  double resistance_ohm = 2.0;             // armature resistance
  double torque_constant_Nm_per_A = 0.02;  // = back-EMF constant [V s/rad]
  double inertia_kgm2 = 2.0e-6;            // motor + gearbox, reflected to the motor shaft
  double viscous_Nms_per_rad = 1.0e-6;     // bearing drag at the motor
  double coulomb_Nm = 1.0e-3;              // gearbox + screw nut friction at the motor
  double gear_ratio = 10.0;                // motor turns per screw turn
  double screw_pitch_mm = 1.0;             // carriage travel per screw turn [mm]
  double screw_efficiency = 0.5;           // lead screws are not back-drivable below 0.5
  double current_limit_A = 3.0;            // drive current limit
  double travel_min_mm = -1.0;             // hard stops of the carriage
  double travel_max_mm = 50.0;
};

struct SensorParams {
  // Load cell + bridge amplifier.
  double force_gain_V_per_N = 2.0;
  double force_offset_V = 0.08;       // unloaded output: what `tare` removes
  double force_noise_N = 0.0015;      // white noise, 1 sigma [N]
  double adc_lsb_V = 20.0 / 65536.0;  // 16-bit converter over +-10 V
  // Linear potentiometer on the carriage.
  double position_gain_V_per_mm = 0.2;  // 10 V over 50 mm
  double position_offset_V = 0.05;
  double position_noise_mm = 0.001;
  // IOP transducer.
  double iop_gain_V_per_mmHg = 0.1;
  double iop_offset_V = 0.0;
  double iop_noise_mmHg = 0.05;
};

struct IopLineParams {
  double pump_max_mmHg = 40.0;          // steady pressure at full pump command
  double time_constant_s = 0.5;         // pressure line + eye compliance
  double indentation_mmHg_per_N = 5.0;  // pressing the cornea raises IOP
  double leak_after_puncture =
      0.0;  // fractional pressure loss through the incision (off by default)
  double initial_mmHg = 0.0;
};

struct SwitchParams {
  double home_switch_mm = 0.5;  // home limit closes at or below this carriage position
  double end_switch_mm = 46.0;  // end limit closes at or above
};

// The eye on its holder and the tissue ground truth (our continuous reading of the
// paper's Eq. 1, see docs/model.md): toe, linear pre-cut rise to the puncture at
// x_pi(IOP), a short drop, a Stribeck-like cutting plateau, linear unloading to zero at
// x_pf(IOP), then zero.
struct TissueParams {
  double surface_mm = 20.0;  // carriage position where the keratome tip touches the cornea
  double toe_slope_N_per_mm = 0.0066;     // a
  double toe_end_mm = 0.75;               // x1
  double precut_slope_N_per_mm = 0.078;   // b
  double cut_log_gain_N = -0.004;         // d
  double cut_log_origin_mm = 3.282;       // e
  double cut_linear_per_mm = -0.495;      // f
  double cut_iop_gain_N_per_mmHg = 0.02;  // g
  double cut_offset_N = -0.114;           // plateau offset below the puncture peak
  double cut_end_mm = 6.89;               // start of unloading
  double drop_width_mm = 0.05;            // puncture drop from peak to plateau
  double release_width_mm = 0.2;          // force released over this withdrawal from the front
  // Table 1 of the paper: puncture and final depth against IOP [mmHg -> mm].
  double table_iop_mmHg[4] = {15, 16, 17, 18};
  double table_xpi_mm[4] = {3.55, 3.75, 3.96, 4.30};
  double table_xpf_mm[4] = {9.35, 9.55, 9.83, 10.03};
  double tear_noise_N = 0.0008;       // plateau fluctuation (tearing), 1 sigma
  double tear_correlation_mm = 0.05;  // its correlation length along the cut
  // Eyes differ: every new eye draws its stiffness scale, puncture depth and cutting-force
  // scale around the nominal values with these spreads (1 sigma), all multiplied by
  // eye_variability (1 = the default spread, 0 = identical eyes).
  double eye_variability = 1.0;
  double eye_stiffness_sigma = 0.10;    // relative, pre-cut stiffness (toe and slope)
  double eye_puncture_sigma_mm = 0.12;  // shift of x_pi
  double eye_cutting_sigma = 0.06;      // relative, cutting plateau
};

struct PhysicsParams {
  MotorScrewParams motor;
  SensorParams sensors;
  IopLineParams iop;
  SwitchParams switches;
  TissueParams tissue;
  double step_s = 1.0e-4;  // integration step (10 kHz)
  std::uint64_t seed = 1;
};

}  // namespace rig::sim
