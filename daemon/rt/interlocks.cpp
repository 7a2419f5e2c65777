#include "interlocks.hpp"

#include <cmath>

namespace rig::rt {

InterlockVerdict Interlocks::check(const CycleInput& in, const RunStateMachine& machine,
                                   double following_error_mm) noexcept {
  const RunState state = machine.state();
  if (state == RunState::kEStop) return {};
  if (in.inputs.estop) return {FaultCode::kEstopInput, 1.0};
  if (state == RunState::kFault || !is_motion_state(state))
    return {};  // at rest: reported, not faulted
  if (in.link_lost) return {FaultCode::kLinkLost, in.unanswered_ms};
  const InterlockVerdict daq = check_daq(in);
  if (daq.code != FaultCode::kNone) return daq;
  return check_motion(in, machine, following_error_mm);
}

// Control over the DAQ's outputs is lost although it answers: it refuses rigd's writes, its
// own watchdog has switched the outputs off, or it rebooted (outputs reset, rigd's next
// write would start the motor again without anyone deciding so).
InterlockVerdict Interlocks::check_daq(const CycleInput& in) noexcept {
  if (in.daq_restarted) return {FaultCode::kDaqRestarted, 0.0};
  // Value: how many writes in a row were lost; 0 when the DAQ refused them outright.
  if (in.failed_writes >= s_.safety.max_failed_writes) {
    return {FaultCode::kDaqWriteFailed,
            in.write_refused ? 0.0 : static_cast<double>(in.failed_writes)};
  }
  if (in.io_ok && in.inputs.daq_watchdog_tripped) return {FaultCode::kDaqWatchdogTripped, 1.0};
  return {};
}

InterlockVerdict Interlocks::check_motion(const CycleInput& in, const RunStateMachine& machine,
                                          double following_error_mm) noexcept {
  const RunState state = machine.state();
  if (in.overrun_storm) return {FaultCode::kOverrunStorm, 0.0};
  if (in.service_fault != FaultCode::kNone) return {in.service_fault, 0.0};
  if (!in.io_ok) return {};  // values are held from the last good read: judge them next cycle
  if (in.inputs.drive_fault) return {FaultCode::kDriveFault, 1.0};
  if (machine.tared() && std::abs(in.force_N) > s_.safety.force_limit_N) {
    return {FaultCode::kForceLimit, in.force_N};
  }
  if (in.inputs.end_limit) return {FaultCode::kEndLimit, in.position_mm};
  if (in.inputs.home_limit && state != RunState::kHoming)
    return {FaultCode::kHomeLimit, in.position_mm};
  const bool searching_home = state == RunState::kHoming && !machine.homed();
  if (machine.homed() && !searching_home &&
      (in.position_mm < s_.motion.soft_min_mm || in.position_mm > s_.motion.soft_max_mm)) {
    return {FaultCode::kSoftLimit, in.position_mm};
  }
  if (state != RunState::kArmed &&
      std::abs(following_error_mm) > s_.safety.max_following_error_mm) {
    // Searching home, a carriage that stops is at a hard stop: the home switch never closed.
    if (searching_home)
      return {FaultCode::kHomingFailed, std::abs(in.raw_position_mm - machine.homing_start_mm())};
    return {FaultCode::kFollowingError, following_error_mm};
  }
  if (force_channel_stuck(in, machine)) return {FaultCode::kStuckForce, in.force_N};
  if (iop_out_of_band(in, machine)) return {FaultCode::kIopOutOfRange, in.iop_mmHg};
  return {};
}

// A leak (a burst line, a torn eye) during the cut changes the tissue the blade meets: the
// run would be measured at an unknown pressure. The regulator settled the IOP before the
// cut started, so any lasting excursion from the target is a fault.
bool Interlocks::iop_out_of_band(const CycleInput& in, const RunStateMachine& machine) noexcept {
  if (machine.state() != RunState::kCutting) {
    iop_out_of_band_s_ = 0.0;
    return false;
  }
  const bool outside = std::abs(in.iop_mmHg - machine.params().iop_mmHg) > s_.iop.fault_band_mmHg;
  iop_out_of_band_s_ = outside ? iop_out_of_band_s_ + in.dt_s : 0.0;
  return iop_out_of_band_s_ * 1e3 >= s_.iop.fault_after_ms;
}

bool Interlocks::force_channel_stuck(const CycleInput& in,
                                     const RunStateMachine& machine) noexcept {
  constexpr double kInsideTissue_mm = 0.5;
  const bool cutting_tissue = machine.state() == RunState::kCutting &&
                              machine.phase() == CutPhase::kInsert &&
                              in.position_mm > s_.motion.surface_mm + kInsideTissue_mm;
  if (!cutting_tissue) {
    identical_force_cycles_ = 0;
    return false;
  }
  // A live load cell is never bit-identical for long: its noise spans many ADC steps.
  identical_force_cycles_ = in.force_volts == last_force_volts_ ? identical_force_cycles_ + 1 : 0;
  last_force_volts_ = in.force_volts;
  return identical_force_cycles_ >= s_.safety.stuck_force_cycles;
}

}  // namespace rig::rt
