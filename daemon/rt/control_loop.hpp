#pragma once
// The real-time loop. Each cycle: read DAQ -> calibrate -> commands -> interlocks -> state
// machine -> velocity and IOP control -> write DAQ -> publish. It reaches the hardware
// only through the narrow driver interfaces, and the rest of rigd only through
// LoopChannels. No allocation, no blocking, no I/O beyond the drivers, no logging.
#include <array>
#include <atomic>
#include <cstdint>

#include "cycle_types.hpp"
#include "interlocks.hpp"
#include "loop_channels.hpp"
#include "loop_settings.hpp"
#include "rig/drivers/actuator_drive.hpp"
#include "rig/drivers/analog_input.hpp"
#include "rig/drivers/digital_io.hpp"
#include "rig/drivers/loop_clock.hpp"
#include "run_state_machine.hpp"
#include "status_snapshot.hpp"
#include "velocity_controller.hpp"

namespace rig::rt {

struct LoopHardware {
  drivers::AnalogInput* analog = nullptr;
  drivers::DigitalIo* digital = nullptr;
  drivers::ActuatorDrive* drive = nullptr;
  drivers::LoopClock* clock = nullptr;
};

class ControlLoop final : public EventSink {
 public:
  ControlLoop(const LoopSettings& settings, const LoopHardware& hardware, LoopChannels& channels);

  // RT thread body: runs on absolute deadlines until `stop` is set, then leaves the motor off.
  void run(const std::atomic<bool>& stop) noexcept;
  // Runs for a span of the clock's time (tests with a virtual clock) [ns].
  void run_for(std::int64_t duration_ns) noexcept;

  void emit(const Event& event) noexcept override;
  const RunStateMachine& machine() const noexcept { return machine_; }
  std::int64_t period_ns() const noexcept { return period_ns_; }

 private:
  void start_timing() noexcept;
  void wait_and_cycle() noexcept;
  void cycle(std::int64_t now_ns, std::int64_t latency_ns) noexcept;
  void read_inputs(CycleInput& in, std::int64_t now_ns, std::int64_t latency_ns) noexcept;
  void judge_link(CycleInput& in, std::int64_t now_ns, std::int64_t latency_ns) noexcept;
  void drain_commands(const CycleInput& in) noexcept;
  drivers::DriveCommand control(const CycleInput& in, const MotionRequest& motion) noexcept;
  drivers::IoStatus write_outputs(
      const drivers::DriveCommand& command) noexcept;  // the first failure
  void note_write(drivers::IoStatus written, bool read_ok) noexcept;
  // run_id: the run this cycle's sample belongs to (0: none) [archive run id].
  void publish(const CycleInput& in, const drivers::DriveCommand& command, float latency_us,
               std::int64_t run_id) noexcept;
  void publish_status(const CycleInput& in, const drivers::DriveCommand& command) noexcept;
  bool note_missed(std::int64_t missed_deadlines) noexcept;
  void shut_down() noexcept;
  void push_event(const Event& event) noexcept;
  void release_held_events() noexcept;

  LoopSettings s_;
  LoopHardware hw_;
  LoopChannels* ch_;
  RunStateMachine machine_;
  Interlocks interlocks_;
  VelocityController controller_;
  std::int64_t period_ns_;
  // [s] the longest step the reference and timers take at once: the DAQ's watchdog plus a few
  // periods of reply latency, at least 10 periods (see LoopSettings::daq_watchdog_ms).
  double max_step_s_;
  std::int64_t start_ns_ = 0;
  std::int64_t next_deadline_ns_ = 0;
  std::int64_t previous_now_ns_ = 0;
  std::uint64_t cycle_ = 0;
  bool timing_started_ = false;
  // A cycle's events until its sample is published (see emit); a cycle emits a handful.
  std::array<Event, 16> held_events_{};
  std::size_t held_count_ = 0;
  bool holding_events_ = false;
  bool arrived_ = false;
  bool overrun_storm_ = false;
  int consecutive_misses_ = 0;
  int failed_writes_ = 0;       // output writes in a row refused in cycles whose read succeeded
  bool write_refused_ = false;  // the last failed write was an explicit refusal (else lost)
  bool have_frame_ = false;     // a valid frame was read (its sequence is the reference)
  std::int64_t unanswered_ns_ = 0;
  std::int64_t last_valid_reply_ns_ =
      0;  // on-time cycles without a valid reply since the last one [ns]
  double last_position_mm_ = 0.0;
  double velocity_mm_s_ = 0.0;
  drivers::AnalogFrame last_frame_{};
  drivers::DigitalInputs last_inputs_{};
  // Overruns within the storm window: the deadline index each one happened at and the deadlines
  // it lost, oldest first, with their sum [periods] (no allocation: a fixed ring).
  struct MissedDeadlines {
    std::uint64_t deadline = 0;
    std::int64_t missed = 0;
  };
  // Overruns are at least two deadlines apart (their own and one lost): the longest window
  // allowed holds at most half as many, so the ring never overwrites one still in the window.
  static constexpr int kMaxStormWindowDeadlines = 2000;
  std::array<MissedDeadlines, kMaxStormWindowDeadlines / 2> overruns_{};
  std::size_t overrun_count_ = 0;   // overruns ever noted (next slot)
  std::size_t oldest_overrun_ = 0;  // the oldest still inside the window
  std::int64_t missed_in_window_ = 0;
  std::uint64_t deadline_index_ = 0;  // deadlines since the loop started, met or missed
  std::uint64_t last_command_id_ = 0;
  CommandResult last_command_result_ = CommandResult::kPending;
  std::array<StatusSnapshot::CommandAnswer, StatusSnapshot::kRecentAnswers> recent_answers_{};
  std::uint64_t answer_count_ = 0;
};

}  // namespace rig::rt
