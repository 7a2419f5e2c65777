#pragma once
// The whole rig in one process: physics, the simulated DAQ, a virtual clock and the real
// control loop. Runs faster than real time and deterministically from its seed; used by
// tests, by `rig sim generate` (runs for the model lab) and by the haptics' live source.
#include <functional>
#include <memory>
#include <vector>

#include "control_loop.hpp"
#include "loop_channels.hpp"
#include "rig/sim/rig_physics.hpp"
#include "sim_daq.hpp"
#include "virtual_clock.hpp"

namespace rig::sim {

// Loop settings whose calibration matches the simulated sensors.
rt::LoopSettings loop_settings_for(const PhysicsParams& physics);

struct RecordedRun {
  std::vector<rt::Sample> samples;
  std::vector<rt::Event> events;
  rt::StatusSnapshot final_status{};
};

class SimulatedRig {
 public:
  SimulatedRig(const PhysicsParams& physics, const std::vector<HiddenEffect>& effects,
               const rt::LoopSettings& loop);
  explicit SimulatedRig(const PhysicsParams& physics = {},
                        const std::vector<HiddenEffect>& effects = {});

  // Sends a command and runs cycles until the loop has answered it.
  rt::CommandResult command(rt::CommandKind kind, const rt::RunParams& params = {});
  void advance(double seconds);
  // Runs until `done(status)` or the virtual timeout [s]; returns whether done.
  bool run_until(const std::function<bool(const rt::StatusSnapshot&)>& done, double timeout_s);
  rt::StatusSnapshot status() { return channels_->status.read(); }

  // Home (if needed), tare (if needed), cut with `params` and wait for the end of the run.
  RecordedRun record_run(const rt::RunParams& params, double timeout_s = 120.0);
  void drain(std::vector<rt::Sample>& samples, std::vector<rt::Event>& events);

  RigPhysics& physics() { return *physics_; }
  drivers::SimDaq& daq() { return *daq_; }
  drivers::VirtualClock& clock() { return *clock_; }
  rt::LoopChannels& channels() { return *channels_; }
  rt::ControlLoop& loop() { return *loop_; }
  double time_s() { return static_cast<double>(clock_->now_ns()) * 1e-9; }

 private:
  std::unique_ptr<RigPhysics> physics_;
  std::unique_ptr<drivers::SimDaq> daq_;
  std::unique_ptr<drivers::VirtualClock> clock_;
  std::unique_ptr<rt::LoopChannels> channels_;
  std::unique_ptr<rt::ControlLoop> loop_;
  std::uint64_t next_command_id_ = 1;
  std::int64_t next_run_id_ = 1;
};

}  // namespace rig::sim
