#pragma once
// Simulated cuts for the lab's small tests (reports, paper model, real-data checks).
#include <string>
#include <vector>

#include "run_generator.hpp"

namespace rig::model::test_runs {

inline RunData simulated_cut(double hold_s = 0.0, double depth_mm = 12.0, double iop_mmHg = 15.0,
                             std::uint64_t seed = 1, const std::vector<std::string>& hidden = {}) {
  sim::GeneratorOptions g;
  for (const auto& text : hidden) {
    std::string error;
    g.effects.push_back(*sim::parse_hidden_effect(text, error));
  }
  sim::RunSpec spec;
  spec.depth_mm = depth_mm;
  spec.hold_s = hold_s;
  spec.iop_mmHg = iop_mmHg;
  spec.seed = seed;
  spec.eye_id = "sim-" + std::to_string(seed);
  return sim::generate_run(g, spec);
}

}  // namespace rig::model::test_runs
