#include "run_types.hpp"

namespace rig::rt {

std::string_view to_string(RunState state) noexcept {
  constexpr std::string_view kNames[] = {"Idle",       "Homing", "Ready", "Armed", "Cutting",
                                         "Retracting", "Done",   "Fault", "EStop"};
  return kNames[static_cast<int>(state)];
}

std::string_view to_string(CutPhase phase) noexcept {
  constexpr std::string_view kNames[] = {"none", "approach", "insert", "hold", "retract"};
  return kNames[static_cast<int>(phase)];
}

std::string_view to_string(FaultCode fault) noexcept {
  constexpr std::string_view kNames[] = {"none",
                                         "e-stop button pressed",
                                         "e-stop commanded",
                                         "DAQ link lost",
                                         "force limit exceeded",
                                         "soft travel limit",
                                         "end limit switch",
                                         "home limit switch",
                                         "loop overrun storm",
                                         "motor drive fault",
                                         "following error",
                                         "force sensor stuck",
                                         "IOP did not settle",
                                         "IOP out of range",
                                         "homing failed",
                                         "recorder overflow",
                                         "archive write failed",
                                         "camera lost",
                                         "DAQ write failed",
                                         "DAQ watchdog tripped",
                                         "DAQ restarted"};
  return kNames[static_cast<int>(fault)];
}

std::string_view to_string(CommandResult result) noexcept {
  constexpr std::string_view kNames[] = {"pending",
                                         "accepted",
                                         "refused: not homed",
                                         "refused: load cell not tared",
                                         "refused: e-stop latched (reset first)",
                                         "refused: e-stop button still pressed",
                                         "refused: rig in fault (reset first)",
                                         "refused: rig is busy",
                                         "refused: not allowed in this state",
                                         "refused: carriage not at park (home first)",
                                         "refused: invalid parameters",
                                         "refused: DAQ link is down"};
  return kNames[static_cast<int>(result)];
}

std::string_view to_string(CommandKind kind) noexcept {
  constexpr std::string_view kNames[] = {"home", "tare", "arm", "start", "stop", "estop", "reset"};
  return kNames[static_cast<int>(kind)];
}

std::string_view to_string(EventKind kind) noexcept {
  constexpr std::string_view kNames[] = {"state",       "fault",     "command",
                                         "run_started", "run_ended", "iop_settled",
                                         "contact",     "tared",     "homed"};
  return kNames[static_cast<int>(kind)];
}

bool is_motion_state(RunState state) noexcept {
  return state == RunState::kHoming || state == RunState::kCutting ||
         state == RunState::kRetracting || state == RunState::kArmed;
}

}  // namespace rig::rt
