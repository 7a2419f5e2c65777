#pragma once
// Runs of the simulated rig as run-CSV data, for the model lab's tests, the demo data and
// `rig sim generate`: each run is a fresh simulated eye cut through the real control loop
// on the virtual clock, with the chosen hidden effects.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "rig/sim/extra_force.hpp"
#include "rig/sim/hidden_effect.hpp"
#include "rig/sim/physics_params.hpp"
#include "run_data.hpp"

namespace rig::sim {

struct RunSpec {
  double iop_mmHg = 15.0;
  double velocity_mm_s = 2.0;
  double depth_mm = 14.0;
  double hold_s = 0.0;
  // Stops on the way in [mm from the surface], each held pause_s[k] seconds (0 = none).
  double pause_depth_mm[2] = {0.0, 0.0};
  double pause_s[2] = {0.0, 0.0};
  double covariate_value = 2.0;              // the eye's value of the covariate (post-mortem hours)
  std::map<std::string, double> extra_meta;  // more numeric metadata (other covariates)
  std::uint64_t seed = 1;
  std::string eye_id;
};

struct GeneratorOptions {
  PhysicsParams physics;
  std::vector<HiddenEffect> effects;
  std::string covariate_key = "post_mortem_h";  // metadata key of the eye's covariate value
  // A force law from outside the catalogue, made for each run (nullptr = none).
  std::function<std::shared_ptr<const ExtraForce>(const RunSpec&)> extra_force;
};

// The one protocol every model-lab scenario uses, whatever the hidden effect, so that no
// protocol gives the answer away: 12 mm deep (past x_pf), a 1.5 s stop at 2 mm (before the
// puncture), a 2 s stop at 5.5 mm (after it, on the cutting plateau) and 1 s at depth.
void apply_standard_protocol(RunSpec& spec);

// A simulated run the rig's interlocks stopped (force limit, stall, ...): what() names the
// eye, its settings and the fault.
struct RunFaulted : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws RunFaulted when the run does not end `Done`.
model::RunData generate_run(const GeneratorOptions& options, const RunSpec& spec);

// A balanced design: every IOP x velocity, covariate values spread over the runs; with
// `standard_protocol`, depth and hold are replaced by apply_standard_protocol.
std::vector<RunSpec> design_runs(const std::vector<double>& iops,
                                 const std::vector<double>& velocities,
                                 const std::vector<double>& covariates, double depth_mm,
                                 double hold_s, std::uint64_t seed);

}  // namespace rig::sim
