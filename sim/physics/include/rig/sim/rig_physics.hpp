#pragma once
// The whole simulated rig: motor + screw + carriage, eye and tissue, IOP line, sensors,
// switches, and the DAQ's own communication watchdog. Time only moves through
// advance_to(), so a caller can run it on a wall clock (rig-sim) or a virtual one (tests).
#include <cstdint>
#include <memory>
#include <vector>

#include "rig/drivers/actuator_drive.hpp"
#include "rig/drivers/analog_input.hpp"
#include "rig/drivers/digital_io.hpp"
#include "rig/sim/active_effects.hpp"
#include "rig/sim/iop_line.hpp"
#include "rig/sim/motor_screw.hpp"
#include "rig/sim/physics_params.hpp"
#include "rig/sim/random_source.hpp"
#include "rig/sim/sensor_chain.hpp"
#include "rig/sim/tissue_truth.hpp"

namespace rig::sim {

// Faults a test (or the demo's test panel) can inject into the rig itself.
struct InjectedFaults {
  bool estop_pressed = false;     // the e-stop button (no hardware relay is modelled)
  bool stuck_force = false;       // load-cell channel freezes at its last value
  bool end_limit_forced = false;  // end switch closed regardless of position
  bool home_limit_forced = false;
  double extra_force_N = 0.0;  // collision / overload added to the load cell
  double iop_leak_fraction =
      0.0;  // a burst line or torn eye: the pressure the pump can hold falls by this fraction
  bool drive_fault =
      false;  // the drive flags a fault (e.g. over-temperature) and keeps its power stage on
  bool carriage_jammed =
      false;  // the lead screw seizes: the carriage stops whatever the motor does
  double position_offset_mm = 0.0;  // the potentiometer reads this much further (slipped coupling)
  bool home_switch_broken = false;  // the home switch never closes
  bool writes_rejected =
      false;  // the DAQ refuses writes to its outputs (answers with an exception)
};

struct RigTruth {
  double time_s = 0.0;
  double carriage_mm = 0.0;
  double velocity_mm_s = 0.0;
  double tip_depth_mm = 0.0;
  double force_N = 0.0;
  double iop_mmHg = 0.0;
  bool punctured = false;
  bool motor_powered = false;
  double motor_off_time_s =
      -1.0;  // last time motor power went from on to off [s, accountable time]
  // how long the host had written nothing when motor power last went off [s]: ~0 when rigd
  // switched it off, the watchdog's time when the DAQ did; judged on the DAQ's own clock.
  double motor_off_silence_s = -1.0;
  // time_s less the stalls of rig-sim itself (excuse_own_stall) [s]: the clock that latencies
  // of rigd are measured on, so that a busy host's preemption of the simulator is not blamed on
  // rigd.
  double accountable_time_s = 0.0;
  bool watchdog_tripped = false;
  std::uint64_t camera_trigger_edges = 0;
};

class RigPhysics {
 public:
  explicit RigPhysics(const PhysicsParams& params, const std::vector<HiddenEffect>& effects = {});

  void advance_to(double time_s);  // integrates in fixed steps up to time_s
  double time_s() const { return time_s_; }

  // DAQ side. Every output write feeds the DAQ's communication watchdog.
  void write_outputs(const drivers::DriveCommand& drive, const drivers::DigitalOutputs& digital);
  void set_watchdog_ms(int watchdog_ms) { watchdog_s_ = watchdog_ms * 1e-3; }
  // The DAQ reboots: outputs off, watchdog off, its conversion counter starts again at 0.
  void restart_daq();
  // The DAQ's watchdog trips as if rigd had fallen silent: outputs off, flag set until the next
  // write.
  void trip_watchdog();
  // The simulator itself was off the CPU for stall_s [s] (a busy host) and is about to catch up:
  // the world moves on through it, as a real one would, but a real DAQ, never preempted, heard
  // rigd's writes that were queued meanwhile. So its watchdog does not count the stall as
  // silence, and accountable time (motor-off latencies) leaves it out. Call before advance_to().
  void excuse_own_stall(double stall_s);
  drivers::AnalogFrame analog_frame() const { return frame_; }
  drivers::DigitalInputs digital_inputs() const;

  InjectedFaults& faults() { return faults_; }
  RigTruth truth() const;
  const TissueTruth& tissue() const { return tissue_; }
  const PhysicsParams& params() const { return params_; }

  // A fresh eye on the holder; `covariate` is its value of the hidden covariate.
  void mount_new_eye(double covariate_value);
  void set_auto_new_eye(bool enabled) { auto_new_eye_ = enabled; }
  void place_carriage(double position_mm) { motor_.set_position_mm(position_mm); }
  void set_iop(double iop_mmHg) { iop_.set_pressure_mmHg(iop_mmHg); }
  void set_next_eye_covariate(double value) { next_covariate_ = value; }
  // A force law from outside the effect catalogue (sim/zoo), on every eye until replaced.
  void set_extra_force(std::shared_ptr<const ExtraForce> law) {
    tissue_.set_extra_force(std::move(law));
  }

 private:
  void step_once();
  bool motor_powered() const;
  bool watchdog_tripped() const;
  void maybe_swap_eye();

  PhysicsParams params_;
  ActiveEffects effects_;
  RandomSource rng_;
  MotorScrew motor_;
  TissueTruth tissue_;
  IopLine iop_;
  SensorChain sensors_;
  InjectedFaults faults_;
  drivers::DriveCommand drive_{};
  drivers::DigitalOutputs digital_out_{};
  drivers::AnalogFrame frame_{};
  double time_s_ = 0.0;
  double eye_mounted_s_ = 0.0;
  double last_write_s_ = 0.0;
  double watchdog_s_ = 0.0;
  bool watchdog_trip_latched_ = false;  // trip_watchdog(), until a write with the motor off
  double motor_off_time_s_ = -1.0;      // [s, accountable time]
  double motor_off_silence_s_ = -1.0;   // host silence when power last went off [s]
  double excused_stalls_s_ = 0.0;       // sum of excuse_own_stall() [s]
  bool was_powered_ = false;
  bool auto_new_eye_ = true;
  double outside_idle_s_ = 0.0;
  double next_covariate_ = 2.0;
  std::uint64_t trigger_edges_ = 0;
  std::uint32_t sequence_ = 0;
};

}  // namespace rig::sim
