#include "run_state_machine.hpp"

#include <cmath>

namespace rig::rt {
namespace {

bool is_one_of(RunState state, std::initializer_list<RunState> states) {
  for (const RunState s : states) {
    if (s == state) return true;
  }
  return false;
}

MotionRequest off() {
  return MotionRequest{};
}

MotionRequest velocity(double velocity_mm_s) {
  MotionRequest m;
  m.mode = MotionRequest::Mode::kVelocity;
  m.velocity_mm_s = velocity_mm_s;
  return m;
}

MotionRequest move_to(double target_mm, double speed_mm_s) {
  MotionRequest m;
  m.mode = MotionRequest::Mode::kMoveTo;
  m.target_mm = target_mm;
  m.speed_mm_s = speed_mm_s;
  return m;
}

MotionRequest hold() {
  MotionRequest m;
  m.mode = MotionRequest::Mode::kHold;
  return m;
}

}  // namespace

void RunStateMachine::emit(EventKind kind, const CycleInput& in, double value) noexcept {
  Event event;
  event.kind = kind;
  event.run_id = (run_open_ || state_ == RunState::kArmed) ? params_.run_id : 0;
  event.t_s = in.t_s;
  event.from = state_;
  event.to = state_;
  event.fault = fault_;
  event.value = value;
  events_->emit(event);
}

void RunStateMachine::enter(RunState next, const CycleInput& in) noexcept {
  Event event;
  event.kind = EventKind::kStateChanged;
  event.run_id = run_open_ ? params_.run_id : 0;
  event.t_s = in.t_s;
  event.from = state_;
  event.to = next;
  event.fault = fault_;
  state_ = next;
  reference_reset_pending_ = true;
  events_->emit(event);
}

std::int64_t RunStateMachine::recording_run_id() const noexcept {
  return run_open_ ? params_.run_id : 0;
}

CommandResult RunStateMachine::handle(const Command& command, const CycleInput& in) noexcept {
  CommandResult result = CommandResult::kWrongState;
  // Commands that set the carriage moving wait for a live link: refused once the last
  // kLinkDownMisses requests in a row went unanswered (3 ms at 1 kHz), not for one reply a busy
  // machine lost at that moment (a lone miss refused homing on a CI VM: 1.2 % of reads missed).
  // A tare does not move the carriage and averages only answered reads (accumulate_tare).
  constexpr int kLinkDownMisses = 3;
  const bool moves = command.kind == CommandKind::kHome || command.kind == CommandKind::kArm ||
                     command.kind == CommandKind::kStart;
  if (moves && in.consecutive_misses >= kLinkDownMisses) {
    result = CommandResult::kLinkDown;
  } else
    switch (command.kind) {
      case CommandKind::kEStop:
        fault(FaultCode::kEstopCommand, 0.0, in);
        result = CommandResult::kAccepted;
        break;
      case CommandKind::kReset:
        result = reset(in);
        break;
      case CommandKind::kStop:
        result = stop(in);
        break;
      case CommandKind::kHome:
        result = start_homing(in);
        break;
      case CommandKind::kTare:
        result = start_tare();
        break;
      case CommandKind::kArm:
        result = arm(command, in);
        break;
      case CommandKind::kStart:
        if (state_ == RunState::kArmed) {
          start_requested_ = true;
          result = CommandResult::kAccepted;
        }
        break;
    }
  Event event;
  event.kind = EventKind::kCommand;
  event.run_id = run_open_ ? params_.run_id : command.params.run_id;
  event.t_s = in.t_s;
  event.from = event.to = state_;
  event.command = command.kind;
  event.result = result;
  events_->emit(event);
  return result;
}

CommandResult RunStateMachine::start_homing(const CycleInput& in) noexcept {
  if (state_ == RunState::kFault) return CommandResult::kFaulted;
  if (state_ == RunState::kEStop) return CommandResult::kEstopLatched;
  if (!is_one_of(state_, {RunState::kIdle, RunState::kReady, RunState::kDone}))
    return CommandResult::kBusy;
  homed_ = false;
  home_switch_found_ = false;
  homing_start_mm_ = in.raw_position_mm;
  enter(RunState::kHoming, in);
  return CommandResult::kAccepted;
}

CommandResult RunStateMachine::start_tare() noexcept {
  if (state_ == RunState::kFault) return CommandResult::kFaulted;
  if (state_ == RunState::kEStop) return CommandResult::kEstopLatched;
  if (!is_one_of(state_, {RunState::kIdle, RunState::kReady, RunState::kDone}) || taring()) {
    return CommandResult::kBusy;
  }
  tared_ = false;
  tare_sum_N_ = 0.0;
  tare_remaining_ = s_.safety.tare_cycles;
  return CommandResult::kAccepted;
}

void RunStateMachine::accumulate_tare(const CycleInput& in) noexcept {
  if (tare_remaining_ <= 0 || !in.io_ok) return;
  tare_sum_N_ += in.raw_force_N;
  if (--tare_remaining_ == 0) {
    tare_offset_N_ = tare_sum_N_ / s_.safety.tare_cycles;
    tared_ = true;
    emit(EventKind::kTared, in, tare_offset_N_);
  }
}

CommandResult RunStateMachine::check_arm(const RunParams& p, const CycleInput& in) const noexcept {
  if (state_ == RunState::kEStop) return CommandResult::kEstopLatched;
  if (state_ == RunState::kFault) return CommandResult::kFaulted;
  if (!is_one_of(state_, {RunState::kReady, RunState::kDone})) return CommandResult::kWrongState;
  if (!homed_) return CommandResult::kNotHomed;
  if (!tared_ || taring()) return CommandResult::kNotTared;
  if (in.inputs.estop) return CommandResult::kEstopPressed;
  const MotionSettings& m = s_.motion;
  const bool valid = p.iop_mmHg >= s_.iop.min_mmHg && p.iop_mmHg <= s_.iop.max_mmHg &&
                     p.velocity_mm_s >= m.min_velocity_mm_s &&
                     p.velocity_mm_s <= m.max_velocity_mm_s && p.depth_mm > 0.0 &&
                     p.depth_mm <= m.max_depth_mm && m.surface_mm + p.depth_mm < m.soft_max_mm &&
                     p.hold_s >= 0.0 && p.hold_s <= 600.0 && p.pause_s[0] >= 0.0 &&
                     p.pause_s[0] <= 600.0 && p.pause_s[1] >= 0.0 && p.pause_s[1] <= 600.0;
  if (!valid) return CommandResult::kInvalidParameters;
  if (std::abs(in.position_mm - m.park_mm) > m.park_tolerance_mm) return CommandResult::kNotAtPark;
  return CommandResult::kAccepted;
}

CommandResult RunStateMachine::arm(const Command& command, const CycleInput& in) noexcept {
  const CommandResult verdict = check_arm(command.params, in);
  if (verdict != CommandResult::kAccepted) return verdict;
  params_ = command.params;
  start_requested_ = params_.start_when_settled;
  iop_.set_target(params_.iop_mmHg);
  enter(RunState::kArmed, in);
  return CommandResult::kAccepted;
}

CommandResult RunStateMachine::stop(const CycleInput& in) noexcept {
  if (state_ == RunState::kHoming) {
    homed_ = false;
    enter(RunState::kIdle, in);
  } else if (state_ == RunState::kArmed) {
    start_requested_ = false;
    enter(RunState::kReady, in);
  } else if (state_ == RunState::kCutting || state_ == RunState::kRetracting) {
    end_run(in, /*stopped_by_operator=*/true);
    enter(RunState::kDone, in);
  }
  return CommandResult::kAccepted;
}

CommandResult RunStateMachine::reset(const CycleInput& in) noexcept {
  if (state_ == RunState::kEStop && in.inputs.estop) return CommandResult::kEstopPressed;
  if (state_ == RunState::kFault || state_ == RunState::kEStop) {
    fault_ = FaultCode::kNone;
    fault_value_ = 0.0;
    homed_ = false;  // position may be stale after a fault: home again
    iop_.disable();
    enter(RunState::kIdle, in);
  }
  return CommandResult::kAccepted;
}

void RunStateMachine::fault(FaultCode code, double value, const CycleInput& in) noexcept {
  const bool estop = code == FaultCode::kEstopInput || code == FaultCode::kEstopCommand;
  if (state_ == RunState::kEStop || (state_ == RunState::kFault && !estop)) return;
  fault_ = code;
  fault_value_ = value;
  start_requested_ = false;
  tare_remaining_ = 0;
  emit(EventKind::kFault, in, value);
  end_run(in, false);
  iop_.disable();
  enter(estop ? RunState::kEStop : RunState::kFault, in);
}

void RunStateMachine::end_run(const CycleInput& in, bool stopped_by_operator) noexcept {
  if (!run_open_) return;
  emit(EventKind::kRunEnded, in, stopped_by_operator ? 1.0 : 0.0);
  run_open_ = false;
  phase_ = CutPhase::kNone;
}

MotionRequest RunStateMachine::step(const CycleInput& in, bool arrived) noexcept {
  accumulate_tare(in);
  MotionRequest motion;
  switch (state_) {
    case RunState::kHoming:
      motion = step_homing(in, arrived);
      break;
    case RunState::kArmed:
      motion = step_armed(in);
      break;
    case RunState::kCutting:
      motion = step_cutting(in);
      break;
    case RunState::kRetracting:
      motion = step_retracting(in, arrived);
      break;
    default:
      motion = off();
      break;
  }
  motion.reset_reference = motion.reset_reference || reference_reset_pending_;
  reference_reset_pending_ = false;
  return motion;
}

MotionRequest RunStateMachine::step_homing(const CycleInput& in, bool arrived) noexcept {
  const MotionSettings& m = s_.motion;
  if (!home_switch_found_) {
    if (in.inputs.home_limit) {
      home_offset_mm_ = m.home_switch_mm - in.raw_position_mm;
      home_switch_found_ = true;
      homed_ = true;
      emit(EventKind::kHomed, in, home_offset_mm_);
      MotionRequest park = move_to(m.park_mm, m.homing_velocity_mm_s);
      park.reset_reference = true;  // coordinates changed under the controller
      return park;
    }
    const double travelled = std::abs(in.raw_position_mm - homing_start_mm_);
    if (travelled > m.max_homing_travel_mm) {
      fault(FaultCode::kHomingFailed, travelled, in);
      return off();
    }
    return velocity(-m.homing_velocity_mm_s);
  }
  if (arrived) {
    enter(RunState::kReady, in);
    return off();
  }
  return move_to(m.park_mm, m.homing_velocity_mm_s);
}

MotionRequest RunStateMachine::step_armed(const CycleInput& in) noexcept {
  if (iop_.settled() && start_requested_) {
    run_open_ = true;
    hold_elapsed_s_ = 0.0;
    pauses_done_ = 0;
    pause_elapsed_s_ = 0.0;
    phase_ = CutPhase::kApproach;
    enter(RunState::kCutting, in);
    emit(EventKind::kRunStarted, in, params_.velocity_mm_s);
    return velocity(params_.velocity_mm_s);
  }
  if (!iop_.settled() && iop_.time_since_target_s() > s_.iop.settle_timeout_s) {
    fault(FaultCode::kIopNotSettled, in.iop_mmHg, in);
  }
  return off();
}

MotionRequest RunStateMachine::step_cutting(const CycleInput& in) noexcept {
  const MotionSettings& m = s_.motion;
  if (phase_ == CutPhase::kApproach && in.position_mm >= m.surface_mm) {
    phase_ = CutPhase::kInsert;
    emit(EventKind::kContact, in, in.position_mm);
  }
  if (phase_ == CutPhase::kHold || in.position_mm >= m.surface_mm + params_.depth_mm) {
    if (phase_ != CutPhase::kHold) {
      phase_ = CutPhase::kHold;
      hold_elapsed_s_ = 0.0;
    } else {
      hold_elapsed_s_ += in.dt_s;
    }
    if (hold_elapsed_s_ >= params_.hold_s) {
      phase_ = CutPhase::kRetract;
      enter(RunState::kRetracting, in);
      return move_to(m.park_mm, m.retract_velocity_mm_s);
    }
    return hold();
  }
  // A stop on the way in: hold where the pause depth was reached, then go on cutting.
  while (pauses_done_ < 2 && params_.pause_s[pauses_done_] <= 0.0) ++pauses_done_;
  if (pauses_done_ < 2 && in.position_mm >= m.surface_mm + params_.pause_depth_mm[pauses_done_]) {
    pause_elapsed_s_ += in.dt_s;
    if (pause_elapsed_s_ < params_.pause_s[pauses_done_]) return hold();
    ++pauses_done_;
    pause_elapsed_s_ = 0.0;
  }
  return velocity(params_.velocity_mm_s);
}

MotionRequest RunStateMachine::step_retracting(const CycleInput& in, bool arrived) noexcept {
  if (arrived) {
    end_run(in, false);
    enter(RunState::kDone, in);
    return off();
  }
  return move_to(s_.motion.park_mm, s_.motion.retract_velocity_mm_s);
}

double RunStateMachine::regulate_iop(const CycleInput& in) noexcept {
  if (!iop_.active()) return 0.0;
  const bool was_settled = iop_.settled();
  const double command = iop_.update(in.iop_mmHg, in.dt_s);
  if (!was_settled && iop_.settled()) emit(EventKind::kIopSettled, in, in.iop_mmHg);
  return command;
}

}  // namespace rig::rt
