#pragma once
// Settings of the RT loop, filled from the validated config at setup (units in names).
namespace rig::rt {

struct LinearCalibration {
  double offset_volts = 0.0;    // output at zero
  double units_per_volt = 1.0;  // N/V, mm/V or mmHg/V
  double to_units(double volts) const { return (volts - offset_volts) * units_per_volt; }
};

struct Calibration {
  LinearCalibration force{0.0, 0.5};
  LinearCalibration position{0.05, 5.0};
  LinearCalibration iop{0.0, 10.0};
};

struct MotionSettings {
  double park_mm = 18.0;        // carriage position where runs start and end
  double surface_mm = 20.0;     // carriage position where the tip touches the cornea
  double home_switch_mm = 0.5;  // carriage position at which the home switch closes
  double homing_velocity_mm_s = 4.0;
  double retract_velocity_mm_s = 4.0;
  double min_velocity_mm_s = 0.5;  // allowed cutting velocities
  double max_velocity_mm_s = 4.0;
  double max_depth_mm = 20.0;
  double soft_min_mm = -0.5;  // soft travel limits (homed only)
  double soft_max_mm = 44.0;
  double max_homing_travel_mm = 60.0;
  double park_tolerance_mm = 0.5;
};

struct ControllerGains {
  double feedforward_V_per_mm_s = 1.25;
  double kp_V_per_mm = 60.0;
  double ki_V_per_mm_s = 300.0;
  double max_volts = 12.0;
  double velocity_filter_s = 0.01;  // low-pass of the velocity estimate
};

struct IopSettings {
  double pump_full_scale_mmHg = 40.0;  // feed-forward: IOP at full pump command
  double kp_per_mmHg = 0.02;
  double ki_per_mmHg_s = 0.05;
  double settle_band_mmHg = 0.3;
  double settle_time_s = 1.0;
  double settle_timeout_s = 20.0;
  double min_mmHg = 5.0;
  double max_mmHg = 40.0;
  double fault_band_mmHg = 5.0;   // during a cut ...
  double fault_after_ms = 100.0;  // ... for this long [ms] (a pump step is not a leak)
};

struct SafetySettings {
  double force_limit_N = 2.0;
  // The link is lost after this much time without a valid DAQ reply, counted over the cycles
  // in which rigd itself asked on time (a cycle rigd woke late for is its own overrun) [ms].
  double link_lost_after_ms = 2.0;
  // A storm is a loop that cannot keep its rate, not one that was late now and then: judged by
  // time, as half the deadlines of the last second missed. A cycle that ran 1.2 ms and skipped
  // a deadline still controlled the carriage (5 um at 4 mm/s between two cycles), and a short
  // stall is the DAQ's watchdog's to stop (daq.watchdog_ms); what is left is a loop that runs at
  // half its rate or worse for a second. On a slow 2-core VM (CI, 2026-11-26/27) 7-16 % of the
  // deadlines were missed at rest, in bursts that tripped a 100-deadline window again and again.
  int overrun_storm_missed_cycles = 500;   // deadlines missed [periods] ...
  int overrun_storm_window_cycles = 1000;  // ... within this many deadlines [periods] = storm
  double max_following_error_mm = 1.0;
  int stuck_force_cycles = 50;  // identical force readings while cutting tissue
  // Output writes lost or garbled in a row (reads answered) before the run faults; an explicit
  // refusal counts as all of them. Keep it below daq.watchdog_ms in cycles.
  int max_failed_writes = 3;
  int tare_cycles = 500;
};

struct LoopSettings {
  double rate_hz = 1000.0;
  // The DAQ's communication watchdog (daq.watchdog_ms) [ms]. Through a gap between two cycles
  // shorter than this the DAQ kept driving the motor at the last command, so the constant-
  // velocity reference follows the whole gap (wall time); after a longer one the DAQ has
  // stopped the motor and the run faults ("DAQ watchdog tripped"), so a longer step is cut.
  double daq_watchdog_ms = 5.0;
  Calibration calibration;
  MotionSettings motion;
  ControllerGains gains;
  IopSettings iop;
  SafetySettings safety;
};

}  // namespace rig::rt
