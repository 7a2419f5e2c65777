#include "control_loop.hpp"

#include <algorithm>
#include <cmath>

namespace rig::rt {

ControlLoop::ControlLoop(const LoopSettings& settings, const LoopHardware& hardware,
                         LoopChannels& channels)
    : s_(settings),
      hw_(hardware),
      ch_(&channels),
      machine_(settings, *this),
      interlocks_(settings),
      controller_(settings.gains),
      period_ns_(static_cast<std::int64_t>(std::llround(1e9 / settings.rate_hz))),
      max_step_s_(std::max(10.0 * static_cast<double>(period_ns_),
                           settings.daq_watchdog_ms * 1e6 + 5.0 * static_cast<double>(period_ns_)) *
                  1e-9) {}

// Inside a cycle, before its sample is out, events wait in held_events_: the recorder must
// find a cycle's sample in its ring once it has that cycle's events (a run's end and the
// run's last sample go into one commit). Past the capacity, events go out at once.
void ControlLoop::emit(const Event& event) noexcept {
  if (holding_events_ && held_count_ < held_events_.size()) {
    held_events_[held_count_++] = event;
    return;
  }
  push_event(event);
}

void ControlLoop::push_event(const Event& event) noexcept {
  if (!ch_->recorder_events.try_push(event))
    ch_->counters.event_drops.fetch_add(1, std::memory_order_relaxed);
  if (!ch_->stream_events.try_push(event))
    ch_->counters.event_drops.fetch_add(1, std::memory_order_relaxed);
}

void ControlLoop::release_held_events() noexcept {
  holding_events_ = false;
  for (std::size_t i = 0; i < held_count_; ++i) push_event(held_events_[i]);
  held_count_ = 0;
}

void ControlLoop::start_timing() noexcept {
  if (timing_started_) return;
  timing_started_ = true;
  start_ns_ = hw_.clock->now_ns();
  ch_->counters.start_ns.store(start_ns_, std::memory_order_relaxed);
  previous_now_ns_ = start_ns_;
  next_deadline_ns_ = start_ns_ + period_ns_;
}

void ControlLoop::wait_and_cycle() noexcept {
  hw_.clock->sleep_until(next_deadline_ns_);
  const std::int64_t now = hw_.clock->now_ns();
  const std::int64_t latency = now - next_deadline_ns_;
  ch_->jitter.record(latency);
  cycle(now, latency);
  next_deadline_ns_ += period_ns_;
  const std::int64_t after = hw_.clock->now_ns();
  std::int64_t lost = 0;
  if (after > next_deadline_ns_) {
    ch_->counters.overruns.fetch_add(1, std::memory_order_relaxed);
    // Skip the deadlines already lost instead of bursting to catch up.
    lost = (after - next_deadline_ns_) / period_ns_ + 1;
    ch_->counters.missed_cycles.fetch_add(static_cast<std::uint64_t>(lost),
                                          std::memory_order_relaxed);
    next_deadline_ns_ += lost * period_ns_;
  }
  overrun_storm_ = note_missed(lost);
}

bool ControlLoop::note_missed(std::int64_t missed_deadlines) noexcept {
  deadline_index_ += 1 + static_cast<std::uint64_t>(missed_deadlines);
  const auto window = static_cast<std::uint64_t>(
      std::clamp(s_.safety.overrun_storm_window_cycles, 1, kMaxStormWindowDeadlines));
  // The window's old overruns leave the sum before a new one takes a slot (see overruns_).
  while (oldest_overrun_ < overrun_count_ &&
         deadline_index_ - overruns_[oldest_overrun_ % overruns_.size()].deadline >= window)
    missed_in_window_ -= overruns_[oldest_overrun_++ % overruns_.size()].missed;
  if (missed_deadlines > 0) {
    overruns_[overrun_count_++ % overruns_.size()] = {deadline_index_, missed_deadlines};
    missed_in_window_ += missed_deadlines;
  }
  return missed_in_window_ >=
         std::clamp(s_.safety.overrun_storm_missed_cycles, 1, kMaxStormWindowDeadlines);
}

void ControlLoop::run(const std::atomic<bool>& stop) noexcept {
  start_timing();
  while (!stop.load(std::memory_order_relaxed)) wait_and_cycle();
  shut_down();
}

void ControlLoop::run_for(std::int64_t duration_ns) noexcept {
  start_timing();
  const std::int64_t end = hw_.clock->now_ns() + duration_ns;
  while (next_deadline_ns_ <= end) wait_and_cycle();
}

void ControlLoop::shut_down() noexcept {
  drivers::DriveCommand off{};
  write_outputs(off);
}

void ControlLoop::judge_link(CycleInput& in, std::int64_t now_ns,
                             std::int64_t latency_ns) noexcept {
  const bool woke_late = latency_ns > period_ns_ / 2;
  if (woke_late) ch_->counters.late_wakes.fetch_add(1, std::memory_order_relaxed);
  // Not excused: a failed read that lasted long. Measured under load, a 700 us select() came
  // back after up to 8.5 ms (rigd held off the CPU mid-exchange), but a dead link makes reads
  // long too (reconnect attempts): excusing them hid a dropped link under ASan (fault matrix).
  if (in.io_ok || cycle_ == 0) last_valid_reply_ns_ = now_ns;
  if (in.io_ok) {
    consecutive_misses_ = 0;
    unanswered_ns_ = 0;
  } else {
    ++consecutive_misses_;
    ch_->counters.io_misses.fetch_add(1, std::memory_order_relaxed);
    if (woke_late) {
      // rigd asked late (its own overrun or a stall): the DAQ is not to blame for this cycle.
      ch_->counters.late_wake_misses.fetch_add(1, std::memory_order_relaxed);
    } else {
      // The DAQ had the time since the previous request to answer (at most two periods).
      unanswered_ns_ +=
          std::min(static_cast<std::int64_t>(std::llround(in.dt_s * 1e9)), 2 * period_ns_);
    }
  }
  in.consecutive_misses = consecutive_misses_;
  in.unanswered_ms = static_cast<double>(unanswered_ns_) * 1e-6;
  // A loop that is late again and again cannot excuse every miss: after four times as many
  // failed requests as the limit holds periods, the link counts as lost all the same (the DAQ's
  // watchdog has long stopped the motor). Counted in requests, not wall time: a VM stall that
  // keeps both rigd and the DAQ off the CPU for 100 ms costs a few requests, not 100.
  const double silent_ms = static_cast<double>(now_ns - last_valid_reply_ns_) * 1e-6;
  const double period_ms = static_cast<double>(period_ns_) * 1e-6;
  const int max_failed_requests =
      static_cast<int>(std::ceil(4.0 * s_.safety.link_lost_after_ms / period_ms));
  in.link_lost = !in.io_ok && (in.unanswered_ms >= s_.safety.link_lost_after_ms - 1e-6 ||
                               consecutive_misses_ >= max_failed_requests);
  if (in.link_lost && in.unanswered_ms < s_.safety.link_lost_after_ms) in.unanswered_ms = silent_ms;
}

void ControlLoop::read_inputs(CycleInput& in, std::int64_t now_ns,
                              std::int64_t latency_ns) noexcept {
  in.t_s = static_cast<double>(now_ns - start_ns_) * 1e-9;
  // Busy VMs hold the loop 10-17 ms at a time; a 10-period cap lost ~1-3 % of the cut's velocity.
  in.dt_s = std::clamp(static_cast<double>(now_ns - previous_now_ns_) * 1e-9, 1e-6, max_step_s_);
  previous_now_ns_ = now_ns;
  drivers::AnalogFrame frame;
  drivers::DigitalInputs inputs;
  const drivers::IoStatus analog = hw_.analog->read(frame);
  const drivers::IoStatus digital = hw_.digital->read(inputs);
  in.io_ok = analog == drivers::IoStatus::kOk && digital == drivers::IoStatus::kOk;
  if (in.io_ok) {
    // A counter that goes backwards is a DAQ that started again (u32 wrap-around is a step
    // forwards).
    in.daq_restarted =
        have_frame_ && static_cast<std::int32_t>(frame.sequence - last_frame_.sequence) < 0;
    have_frame_ = true;
    last_frame_ = frame;
    last_inputs_ = inputs;
  }
  judge_link(in, now_ns, latency_ns);
  const Calibration& cal = s_.calibration;
  in.inputs = last_inputs_;
  in.force_volts = last_frame_.force_volts;
  in.raw_force_N = cal.force.to_units(last_frame_.force_volts);
  in.force_N = in.raw_force_N - machine_.tare_offset_N();
  in.raw_position_mm = cal.position.to_units(last_frame_.position_volts);
  in.position_mm = in.raw_position_mm + machine_.home_offset_mm();
  in.iop_mmHg = cal.iop.to_units(last_frame_.iop_volts);
  const double alpha = in.dt_s / (s_.gains.velocity_filter_s + in.dt_s);
  if (cycle_ > 0)
    velocity_mm_s_ += alpha * ((in.position_mm - last_position_mm_) / in.dt_s - velocity_mm_s_);
  last_position_mm_ = in.position_mm;
  in.velocity_mm_s = velocity_mm_s_;
  in.overrun_storm = overrun_storm_;
  in.failed_writes = failed_writes_;
  in.write_refused = write_refused_;
  in.service_fault = ch_->service_fault.load(std::memory_order_relaxed);
}

void ControlLoop::drain_commands(const CycleInput& in) noexcept {
  Command command;
  for (int i = 0; i < 4 && ch_->commands.pop(command); ++i) {  // bounded work per cycle
    last_command_result_ = machine_.handle(command, in);
    last_command_id_ = command.id;
    recent_answers_[answer_count_++ % recent_answers_.size()] = {command.id, last_command_result_};
  }
}

drivers::DriveCommand ControlLoop::control(const CycleInput& in,
                                           const MotionRequest& motion) noexcept {
  drivers::DriveCommand command;
  command.pump_command = machine_.regulate_iop(in);
  if (motion.reset_reference || motion.mode == MotionRequest::Mode::kOff)
    controller_.reset(in.position_mm);
  switch (motion.mode) {
    case MotionRequest::Mode::kOff:
      arrived_ = false;
      return command;
    case MotionRequest::Mode::kHold:
      command.motor_volts = controller_.track_velocity(0.0, in.position_mm, in.dt_s);
      break;
    case MotionRequest::Mode::kVelocity:
      command.motor_volts =
          controller_.track_velocity(motion.velocity_mm_s, in.position_mm, in.dt_s);
      break;
    case MotionRequest::Mode::kMoveTo:
      command.motor_volts = controller_.move_to(motion.target_mm, motion.speed_mm_s, in.position_mm,
                                                in.dt_s, arrived_);
      break;
  }
  command.motor_enable = true;
  return command;
}

drivers::IoStatus ControlLoop::write_outputs(const drivers::DriveCommand& command) noexcept {
  drivers::DigitalOutputs outputs;
  outputs.motor_enable = command.motor_enable;
  const drivers::IoStatus digital = hw_.digital->write(outputs);
  const drivers::IoStatus drive = hw_.drive->write(command);
  return digital != drivers::IoStatus::kOk ? digital : drive;
}

// Only a write that failed in a cycle whose read succeeded counts: after a failed read the
// driver does not write at all, and the link judgement (judge_link) owns that case. An
// explicit refusal is certain at once; a lost or garbled answer (a late reply under load)
// needs safety.max_failed_writes in a row.
void ControlLoop::note_write(drivers::IoStatus written, bool read_ok) noexcept {
  if (written == drivers::IoStatus::kOk) {
    failed_writes_ = 0;
    write_refused_ = false;
  } else if (read_ok) {
    write_refused_ = written == drivers::IoStatus::kRefused;
    failed_writes_ = written == drivers::IoStatus::kRefused
                         ? std::max(failed_writes_ + 1, s_.safety.max_failed_writes)
                         : failed_writes_ + 1;
    ch_->counters.write_failures.fetch_add(1, std::memory_order_relaxed);
  }
}

void ControlLoop::cycle(std::int64_t now_ns, std::int64_t latency_ns) noexcept {
  CycleInput in;
  read_inputs(in, now_ns, latency_ns);
  // The cycle that ends a run (its fault, stop or completion) is the run's last sample: the
  // archive then shows the cycle that saw the fault and its 0 V command, not the one before.
  const std::int64_t run_open_before = machine_.recording_run_id();
  holding_events_ = true;
  drain_commands(in);
  const InterlockVerdict verdict =
      interlocks_.check(in, machine_, controller_.following_error_mm());
  if (verdict.code != FaultCode::kNone) machine_.fault(verdict.code, verdict.value, in);
  constexpr double kAtRest_mm_s = 0.05;  // a move has ended when the carriage is also still
  const MotionRequest motion =
      machine_.step(in, arrived_ && std::abs(in.velocity_mm_s) < kAtRest_mm_s);
  drivers::DriveCommand command = control(in, motion);
  note_write(write_outputs(command), in.io_ok);
  publish(in, command, static_cast<float>(latency_ns) * 1e-3F,
          run_open_before != 0 ? run_open_before : machine_.recording_run_id());
  release_held_events();
  if (machine_.state() == RunState::kFault && command.motor_enable) {
    command = drivers::DriveCommand{};  // publish() faulted the run: stop now, not next cycle
    note_write(write_outputs(command), in.io_ok);
  }
  publish_status(in, command);
  ++cycle_;
  ch_->counters.cycles.store(cycle_, std::memory_order_relaxed);
}

void ControlLoop::publish(const CycleInput& in, const drivers::DriveCommand& command,
                          float latency_us, std::int64_t run_id) noexcept {
  Sample sample;
  sample.cycle = cycle_;
  sample.run_id = run_id;
  sample.t_s = in.t_s;
  sample.position_mm = in.position_mm;
  sample.force_N = in.force_N;
  sample.iop_mmHg = in.iop_mmHg;
  sample.velocity_mm_s = in.velocity_mm_s;
  sample.motor_volts = command.motor_enable ? command.motor_volts : 0.0;
  sample.pump_command = command.pump_command;
  sample.wake_latency_us = latency_us;
  sample.state = machine_.state();
  sample.phase = machine_.phase();
  sample.io_ok = in.io_ok ? 1 : 0;
  if (sample.run_id != 0 && !ch_->recorder.try_push(sample)) {
    ch_->counters.recorder_drops.fetch_add(1, std::memory_order_relaxed);
    machine_.fault(FaultCode::kRecorderOverflow, static_cast<double>(ch_->recorder.capacity()), in);
  }
  if (!ch_->stream.try_push(sample))
    ch_->counters.stream_drops.fetch_add(1, std::memory_order_relaxed);
}

void ControlLoop::publish_status(const CycleInput& in,
                                 const drivers::DriveCommand& command) noexcept {
  StatusSnapshot st;
  st.cycle = cycle_;
  st.t_s = in.t_s;
  st.state = machine_.state();
  st.phase = machine_.phase();
  st.fault = machine_.fault_code();
  st.fault_value = machine_.fault_value();
  st.homed = machine_.homed();
  st.tared = machine_.tared();
  st.taring = machine_.taring();
  st.io_ok = in.io_ok;
  st.consecutive_misses = in.consecutive_misses;
  st.position_mm = in.position_mm;
  st.velocity_mm_s = in.velocity_mm_s;
  st.force_N = in.force_N;
  st.iop_mmHg = in.iop_mmHg;
  st.iop_target_mmHg = machine_.iop().target_mmHg();
  st.iop_regulating = machine_.iop().active();
  st.iop_settled = machine_.iop().settled();
  st.motor_volts = command.motor_volts;
  st.motor_enabled = command.motor_enable;
  st.pump_command = command.pump_command;
  st.home_limit = in.inputs.home_limit;
  st.end_limit = in.inputs.end_limit;
  st.estop_input = in.inputs.estop;
  st.run_id = machine_.recording_run_id();
  st.params = machine_.params();
  st.tare_offset_N = machine_.tare_offset_N();
  st.last_command_id = last_command_id_;
  st.last_command_result = last_command_result_;
  st.recent_answers = recent_answers_;
  st.recent_answer_count = answer_count_;
  ch_->status.publish(st);
}

}  // namespace rig::rt
