#pragma once
// Everything the API reports about the loop, published by the RT thread every cycle.
#include <cstdint>

#include "run_types.hpp"

namespace rig::rt {

struct StatusSnapshot {
  std::uint64_t cycle = 0;
  double t_s = 0.0;
  RunState state = RunState::kIdle;
  CutPhase phase = CutPhase::kNone;
  FaultCode fault = FaultCode::kNone;
  double fault_value = 0.0;
  bool homed = false;
  bool tared = false;
  bool taring = false;
  bool io_ok = false;
  int consecutive_misses = 0;
  double position_mm = 0.0;
  double velocity_mm_s = 0.0;
  double force_N = 0.0;
  double iop_mmHg = 0.0;
  double iop_target_mmHg = 0.0;
  bool iop_regulating = false;
  bool iop_settled = false;
  double motor_volts = 0.0;
  bool motor_enabled = false;
  double pump_command = 0.0;
  bool home_limit = false;
  bool end_limit = false;
  bool estop_input = false;
  std::int64_t run_id = 0;         // run being recorded, 0 if none
  RunParams params{};
  double tare_offset_N = 0.0;
  std::uint64_t last_command_id = 0;
  CommandResult last_command_result = CommandResult::kPending;
};

}  // namespace rig::rt
