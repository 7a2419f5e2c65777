#include "simulated_rig.hpp"

#include <stdexcept>
#include <string>

namespace rig::sim {

rt::LoopSettings loop_settings_for(const PhysicsParams& physics) {
  rt::LoopSettings loop;
  const SensorParams& s = physics.sensors;
  loop.calibration.force = {0.0, 1.0 / s.force_gain_V_per_N};  // offset is tared
  loop.calibration.position = {s.position_offset_V, 1.0 / s.position_gain_V_per_mm};
  loop.calibration.iop = {s.iop_offset_V, 1.0 / s.iop_gain_V_per_mmHg};
  loop.motion.surface_mm = physics.tissue.surface_mm;
  loop.motion.park_mm = physics.tissue.surface_mm - 2.0;
  loop.motion.home_switch_mm = physics.switches.home_switch_mm;
  return loop;
}

SimulatedRig::SimulatedRig(const PhysicsParams& physics, const std::vector<HiddenEffect>& effects,
                           const rt::LoopSettings& loop)
    : physics_(std::make_unique<RigPhysics>(physics, effects)),
      daq_(std::make_unique<drivers::SimDaq>(*physics_)),
      clock_(std::make_unique<drivers::VirtualClock>(*physics_)),
      channels_(std::make_unique<rt::LoopChannels>()) {
  rt::LoopHardware hw{daq_.get(), daq_.get(), daq_.get(), clock_.get()};
  loop_ = std::make_unique<rt::ControlLoop>(loop, hw, *channels_);
}

SimulatedRig::SimulatedRig(const PhysicsParams& physics, const std::vector<HiddenEffect>& effects)
    : SimulatedRig(physics, effects, loop_settings_for(physics)) {}

void SimulatedRig::advance(double seconds) {
  loop_->run_for(static_cast<std::int64_t>(seconds * 1e9));
}

rt::CommandResult SimulatedRig::command(rt::CommandKind kind, const rt::RunParams& params) {
  rt::Command command;
  command.kind = kind;
  command.id = next_command_id_++;
  command.params = params;
  if (!channels_->commands.push(command)) throw std::runtime_error("command queue full");
  for (int i = 0; i < 100; ++i) {
    loop_->run_for(loop_->period_ns());
    const rt::StatusSnapshot st = status();
    if (const auto result = st.answer_to(command.id)) return *result;
  }
  throw std::runtime_error("loop did not answer command " + std::string(rt::to_string(kind)));
}

bool SimulatedRig::run_until(const std::function<bool(const rt::StatusSnapshot&)>& done,
                             double timeout_s) {
  const double end = time_s() + timeout_s;
  while (time_s() < end) {
    loop_->run_for(10 * loop_->period_ns());
    if (done(status())) return true;
  }
  return false;
}

void SimulatedRig::drain(std::vector<rt::Sample>& samples, std::vector<rt::Event>& events) {
  rt::Sample sample;
  while (channels_->recorder.try_pop(sample)) samples.push_back(sample);
  rt::Event event;
  while (channels_->recorder_events.try_pop(event)) events.push_back(event);
  rt::Sample ignored;
  while (channels_->stream.try_pop(ignored)) {
  }
  while (channels_->stream_events.try_pop(event)) {
  }
}

RecordedRun SimulatedRig::record_run(const rt::RunParams& params, double timeout_s) {
  RecordedRun run;
  auto is = [](rt::RunState s) {
    return [s](const rt::StatusSnapshot& st) { return st.state == s; };
  };
  if (!status().homed || status().state != rt::RunState::kReady) {
    command(rt::CommandKind::kHome);
    if (!run_until(is(rt::RunState::kReady), 60.0))
      throw std::runtime_error("simulated rig did not home");
  }
  if (!status().tared) {
    command(rt::CommandKind::kTare);
    if (!run_until([](const rt::StatusSnapshot& st) { return st.tared; }, 5.0))
      throw std::runtime_error("tare did not finish");
  }
  drain(run.samples, run.events);
  run.samples.clear();
  run.events.clear();
  rt::RunParams p = params;
  if (p.run_id == 0) p.run_id = next_run_id_++;
  const rt::CommandResult armed = command(rt::CommandKind::kArm, p);
  if (armed != rt::CommandResult::kAccepted) {
    throw std::runtime_error("arm " + std::string(rt::to_string(armed)));
  }
  const bool ended = run_until(
      [](const rt::StatusSnapshot& st) {
        return st.state == rt::RunState::kDone || st.state == rt::RunState::kFault ||
               st.state == rt::RunState::kEStop;
      },
      timeout_s);
  drain(run.samples, run.events);
  run.final_status = status();
  if (!ended) throw std::runtime_error("simulated run did not end within the time-out");
  return run;
}

}  // namespace rig::sim
