#pragma once
// The run state machine: Idle -> Homing -> Ready -> Armed -> Cutting -> Retracting -> Done,
// plus Fault and EStop. It decides what the carriage should do each cycle and refuses to
// start a run from a bad state. Faults come from Interlocks; recovery is an explicit reset.
#include "cycle_types.hpp"
#include "iop_regulator.hpp"
#include "loop_settings.hpp"

namespace rig::rt {

class RunStateMachine {
 public:
  RunStateMachine(const LoopSettings& settings, EventSink& events)
      : s_(settings), events_(&events), iop_(settings.iop) {}

  CommandResult handle(const Command& command, const CycleInput& in) noexcept;
  // Any fault: motor off this cycle, state Fault (or EStop), the run is closed.
  void fault(FaultCode code, double value, const CycleInput& in) noexcept;
  // Decides this cycle's motion; `arrived` reports the previous move_to completion.
  MotionRequest step(const CycleInput& in, bool arrived) noexcept;
  // Pump command for this cycle [0..1].
  double regulate_iop(const CycleInput& in) noexcept;

  RunState state() const noexcept { return state_; }
  CutPhase phase() const noexcept { return phase_; }
  bool homed() const noexcept { return homed_; }
  bool tared() const noexcept { return tared_; }
  bool taring() const noexcept { return tare_remaining_ > 0; }
  FaultCode fault_code() const noexcept { return fault_; }
  double fault_value() const noexcept { return fault_value_; }
  double tare_offset_N() const noexcept { return tare_offset_N_; }
  double home_offset_mm() const noexcept { return home_offset_mm_; }
  double homing_start_mm() const noexcept { return homing_start_mm_; }  // raw position [mm]
  std::int64_t recording_run_id() const noexcept;
  const RunParams& params() const noexcept { return params_; }
  const IopRegulator& iop() const noexcept { return iop_; }
  bool estop_latched() const noexcept { return state_ == RunState::kEStop; }

 private:
  void enter(RunState next, const CycleInput& in) noexcept;
  void emit(EventKind kind, const CycleInput& in, double value = 0.0) noexcept;
  CommandResult check_arm(const RunParams& params, const CycleInput& in) const noexcept;
  CommandResult arm(const Command& command, const CycleInput& in) noexcept;
  CommandResult stop(const CycleInput& in) noexcept;
  CommandResult reset(const CycleInput& in) noexcept;
  CommandResult start_homing(const CycleInput& in) noexcept;
  CommandResult start_tare() noexcept;
  void accumulate_tare(const CycleInput& in) noexcept;
  MotionRequest step_homing(const CycleInput& in, bool arrived) noexcept;
  MotionRequest step_armed(const CycleInput& in) noexcept;
  MotionRequest step_cutting(const CycleInput& in) noexcept;
  MotionRequest step_retracting(const CycleInput& in, bool arrived) noexcept;
  void end_run(const CycleInput& in, bool stopped_by_operator) noexcept;

  LoopSettings s_;
  EventSink* events_;
  IopRegulator iop_;
  RunState state_ = RunState::kIdle;
  CutPhase phase_ = CutPhase::kNone;
  RunParams params_{};
  bool homed_ = false;
  bool tared_ = false;
  bool home_switch_found_ = false;
  bool start_requested_ = false;
  bool run_open_ = false;
  bool reference_reset_pending_ = false;
  FaultCode fault_ = FaultCode::kNone;
  double fault_value_ = 0.0;
  double tare_offset_N_ = 0.0;
  double tare_sum_N_ = 0.0;
  int tare_remaining_ = 0;
  double home_offset_mm_ = 0.0;
  double homing_start_mm_ = 0.0;
  double hold_elapsed_s_ = 0.0;
  int pauses_done_ = 0;  // stops on the way in already held
  double pause_elapsed_s_ = 0.0;
};

}  // namespace rig::rt
