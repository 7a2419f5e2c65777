#pragma once
// Runs of the simulated rig as run-CSV data, for the model lab's tests, the demo data and
// `rig sim generate`: each run is a fresh simulated eye cut through the real control loop
// on the virtual clock, with the chosen hidden effects.
#include <cstdint>
#include <string>
#include <vector>

#include "rig/sim/hidden_effect.hpp"
#include "rig/sim/physics_params.hpp"
#include "run_data.hpp"

namespace rig::sim {

struct RunSpec {
  double iop_mmHg = 15.0;
  double velocity_mm_s = 2.0;
  double depth_mm = 14.0;
  double hold_s = 0.0;
  double covariate_value = 2.0;  // the eye's value of the covariate (post-mortem hours)
  std::uint64_t seed = 1;
  std::string eye_id;
};

struct GeneratorOptions {
  PhysicsParams physics;
  std::vector<HiddenEffect> effects;
  std::string covariate_key = "post_mortem_h";  // metadata key of the eye's covariate value
};

model::RunData generate_run(const GeneratorOptions& options, const RunSpec& spec);

// A balanced design: every IOP x velocity, covariate values spread over the runs.
std::vector<RunSpec> design_runs(const std::vector<double>& iops, const std::vector<double>& velocities,
                                 const std::vector<double>& covariates, double depth_mm, double hold_s, std::uint64_t seed);

}  // namespace rig::sim
