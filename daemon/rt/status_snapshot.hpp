#pragma once
// Everything the API reports about the loop, published by the RT thread every cycle.
#include <array>
#include <cstdint>
#include <optional>

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
  std::int64_t run_id = 0;  // run being recorded, 0 if none
  RunParams params{};
  double tare_offset_N = 0.0;
  std::uint64_t last_command_id = 0;
  CommandResult last_command_result = CommandResult::kPending;
  // The answers to the most recent commands, newest at recent_answer_count - 1 (mod size).
  // The loop takes up to 4 commands a cycle: two clients that command in the same cycle each
  // find their own answer here, not only the last one's (which left the other waiting: 504).
  struct CommandAnswer {
    std::uint64_t id = 0;
    CommandResult result = CommandResult::kPending;
  };
  static constexpr std::size_t kRecentAnswers = 32;  // 8 cycles at 4 commands each
  std::array<CommandAnswer, kRecentAnswers> recent_answers{};
  std::uint64_t recent_answer_count = 0;

  std::optional<CommandResult> answer_to(std::uint64_t command_id) const noexcept {
    for (const CommandAnswer& a : recent_answers) {
      if (a.id == command_id && command_id != 0) return a.result;
    }
    return std::nullopt;
  }
};

}  // namespace rig::rt
