#pragma once
// Plain data exchanged between the RT loop and the rest of rigd. Everything here is
// trivially copyable: it crosses threads through lock-free rings and triple buffers.
#include <cstdint>
#include <string_view>

namespace rig::rt {

enum class RunState : std::uint8_t {
  kIdle,
  kHoming,
  kReady,
  kArmed,
  kCutting,
  kRetracting,
  kDone,
  kFault,
  kEStop
};

// Where a cut is: before the eye, inserting, holding at depth, retracting.
enum class CutPhase : std::uint8_t { kNone, kApproach, kInsert, kHold, kRetract };

enum class FaultCode : std::uint8_t {
  kNone,
  kEstopInput,          // e-stop button
  kEstopCommand,        // e-stop from the API / CLI
  kLinkLost,            // DAQ did not answer (time-out, link down, garbage) too many cycles
  kForceLimit,          // load-cell protection
  kSoftLimit,           // carriage left the soft travel range
  kEndLimit,            // far limit switch
  kHomeLimit,           // home switch outside homing
  kOverrunStorm,        // loop missed too many deadlines
  kDriveFault,          // motor drive reported a fault
  kFollowingError,      // carriage does not follow its reference (stall, collision)
  kStuckForce,          // force channel frozen while cutting through tissue
  kIopNotSettled,       // IOP did not settle before the time-out
  kIopOutOfRange,       // IOP left its band during the cut
  kHomingFailed,        // no home switch within the travel
  kRecorderOverflow,    // archive could not keep up: stop rather than lose data
  kArchiveWriteFailed,  // the recorder cannot write the archive (disk full, I/O error)
  kCameraLost,          // no camera frame for camera.lost_after_ms while recording
  kDaqWriteFailed,      // the DAQ refused or lost rigd's output writes although it answers reads
  kDaqWatchdogTripped,  // the DAQ's own watchdog forced the outputs off (rigd was silent too long)
  kDaqRestarted,        // the DAQ's conversion counter went backwards: it rebooted, outputs reset
};

// Answer of the RT loop to a command (the API waits for it).
enum class CommandResult : std::uint8_t {
  kPending,
  kAccepted,
  kNotHomed,
  kNotTared,
  kEstopLatched,
  kEstopPressed,
  kFaulted,
  kBusy,
  kWrongState,
  kNotAtPark,
  kInvalidParameters,
  kLinkDown,
};

enum class CommandKind : std::uint8_t { kHome, kTare, kArm, kStart, kStop, kEStop, kReset };

struct RunParams {
  double iop_mmHg = 15.0;      // IOP to set and hold
  double velocity_mm_s = 2.0;  // constant cutting velocity
  double depth_mm = 14.0;      // insertion depth from the corneal surface
  double hold_s = 0.0;         // hold at depth before retracting
  // Up to two stops on the way in (e.g. one before and one after the puncture), at depths
  // from the surface [mm] in increasing order, each held for pause_s[k] seconds; 0 s = none.
  // Used by the simulated protocols of the model lab (relaxation must be visible everywhere).
  double pause_depth_mm[2] = {0.0, 0.0};
  double pause_s[2] = {0.0, 0.0};
  bool start_when_settled = true;  // start cutting as soon as the IOP settles
  std::int64_t run_id = 0;         // archive id assigned before arming
};

struct Command {
  CommandKind kind = CommandKind::kStop;
  std::uint64_t id = 0;  // echoed in the status so the sender can find its answer
  RunParams params{};
};

struct Sample {
  std::uint64_t cycle = 0;
  std::int64_t run_id = 0;   // 0 when no run is being recorded
  double t_s = 0.0;          // CLOCK_MONOTONIC since loop start, at the read [s]
  double position_mm = 0.0;  // carriage from home
  double force_N = 0.0;      // tared axial force
  double iop_mmHg = 0.0;
  double velocity_mm_s = 0.0;  // filtered carriage velocity
  double motor_volts = 0.0;    // command sent this cycle
  double pump_command = 0.0;
  float wake_latency_us = 0.0F;
  RunState state = RunState::kIdle;
  CutPhase phase = CutPhase::kNone;
  std::uint8_t io_ok = 1;  // 0 when this cycle's DAQ read failed (values are held)
};

enum class EventKind : std::uint8_t {
  kStateChanged,
  kFault,
  kCommand,
  kRunStarted,
  kRunEnded,
  kIopSettled,
  kContact,
  kTared,
  kHomed
};

struct Event {
  EventKind kind = EventKind::kStateChanged;
  std::int64_t run_id = 0;
  double t_s = 0.0;
  RunState from = RunState::kIdle;
  RunState to = RunState::kIdle;
  FaultCode fault = FaultCode::kNone;
  CommandKind command = CommandKind::kStop;
  CommandResult result = CommandResult::kPending;
  double value = 0.0;  // fault: measured value (force, position, misses...); tare: offset
};

std::string_view to_string(RunState state) noexcept;
std::string_view to_string(CutPhase phase) noexcept;
std::string_view to_string(FaultCode fault) noexcept;
std::string_view to_string(CommandResult result) noexcept;
std::string_view to_string(CommandKind kind) noexcept;
std::string_view to_string(EventKind kind) noexcept;
bool is_motion_state(RunState state) noexcept;

}  // namespace rig::rt
