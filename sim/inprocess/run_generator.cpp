#include "run_generator.hpp"

#include <cstdio>
#include <stdexcept>

#include "simulated_rig.hpp"

namespace rig::sim {
namespace {

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

}  // namespace

model::RunData generate_run(const GeneratorOptions& options, const RunSpec& spec) {
  PhysicsParams physics = options.physics;
  physics.seed = spec.seed;
  SimulatedRig rig(physics, options.effects);
  if (options.extra_force) rig.physics().set_extra_force(options.extra_force(spec));
  rig.physics().set_next_eye_covariate(spec.covariate_value);
  rig.physics().mount_new_eye(spec.covariate_value);
  rt::RunParams params;
  params.iop_mmHg = spec.iop_mmHg;
  params.velocity_mm_s = spec.velocity_mm_s;
  params.depth_mm = spec.depth_mm;
  params.hold_s = spec.hold_s;
  for (int k = 0; k < 2; ++k) {
    params.pause_depth_mm[k] = spec.pause_depth_mm[k];
    params.pause_s[k] = spec.pause_s[k];
  }
  const RecordedRun run = rig.record_run(params);
  if (run.final_status.state != rt::RunState::kDone) {
    // The rig's interlocks stopped it (an effect large enough to overload the load cell or
    // stall the drive does that on a real rig too): say which, for the eye and its settings.
    throw RunFaulted("simulated run of " + spec.eye_id + " (" + number(spec.velocity_mm_s) +
                     " mm/s, IOP " + number(spec.iop_mmHg) + " mmHg) ended in " +
                     std::string(rt::to_string(run.final_status.state)) + ": " +
                     std::string(rt::to_string(run.final_status.fault)) + " at " +
                     number(run.final_status.fault_value));
  }
  model::RunData data;
  data.source = "sim:" + spec.eye_id;
  data.meta = {{"eye_id", spec.eye_id},
               {"iop_mmHg", number(spec.iop_mmHg)},
               {"velocity_mm_s", number(spec.velocity_mm_s)},
               {"depth_mm", number(spec.depth_mm)},
               {"hold_s", number(spec.hold_s)},
               {options.covariate_key, number(spec.covariate_value)}};
  for (const auto& [key, value] : spec.extra_meta) data.meta.emplace_back(key, number(value));
  model::Channel iop{"iop_meas_mmHg", {}};
  model::Channel motor{"motor_cmd_V", {}};
  const double t0 = run.samples.front().t_s;
  const double surface = physics.tissue.surface_mm;
  for (const rt::Sample& s : run.samples) {
    data.t_s.push_back(s.t_s - t0);
    data.x_mm.push_back(s.position_mm - surface);
    data.force_N.push_back(s.force_N);
    iop.values.push_back(s.iop_mmHg);
    motor.values.push_back(s.motor_volts);
  }
  data.channels = {std::move(iop), std::move(motor)};
  return data;
}

void apply_standard_protocol(RunSpec& spec) {
  spec.depth_mm = 12.0;
  spec.hold_s = 1.0;
  spec.pause_depth_mm[0] = 2.0;
  spec.pause_s[0] = 1.5;
  spec.pause_depth_mm[1] = 5.5;
  spec.pause_s[1] = 2.0;
}

std::vector<RunSpec> design_runs(const std::vector<double>& iops,
                                 const std::vector<double>& velocities,
                                 const std::vector<double>& covariates, double depth_mm,
                                 double hold_s, std::uint64_t seed) {
  std::vector<RunSpec> out;
  std::size_t k = 0;
  for (const double iop : iops) {
    for (const double v : velocities) {
      RunSpec s;
      s.iop_mmHg = iop;
      s.velocity_mm_s = v;
      s.depth_mm = depth_mm;
      s.hold_s = hold_s;
      s.covariate_value = covariates.empty() ? 2.0 : covariates[k % covariates.size()];
      s.seed = seed * 1000 + k;
      s.eye_id = "SIM-" + std::to_string(seed) + "-" + std::to_string(k);
      out.push_back(s);
      ++k;
    }
  }
  return out;
}

}  // namespace rig::sim
