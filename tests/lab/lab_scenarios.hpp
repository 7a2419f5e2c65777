#pragma once
// Datasets of simulated runs with hidden effects, for the model lab's tests.
#include <stdexcept>
#include <string>
#include <vector>

#include "run_generator.hpp"

namespace rig::testing {

// 9 runs: IOP 15/16.5/18 mmHg x 1.5/2.5/3.5 mm/s, post-mortem 0.5..3.5 h; 12 mm deep (past
// x_pf), or 6 mm with a 3 s hold when the effect needs holds.
inline std::vector<model::RunData> scenario_runs(const std::vector<std::string>& hidden, std::uint64_t seed = 3,
                                                 bool holds = false) {
  sim::GeneratorOptions g;
  for (const auto& spec : hidden) {
    std::string error;
    const auto effect = sim::parse_hidden_effect(spec, error);
    if (!effect) throw std::invalid_argument(error);
    g.effects.push_back(*effect);
    holds = holds || effect->kind == sim::EffectKind::kStressRelaxation;
  }
  std::vector<model::RunData> runs;
  for (const auto& spec : sim::design_runs({15, 16.5, 18}, {1.5, 2.5, 3.5}, {0.5, 2.0, 3.5, 1.0, 3.0, 2.5, 1.5, 0.8, 3.2},
                                           holds ? 6.0 : 12.0, holds ? 3.0 : 0.0, seed)) {
    runs.push_back(sim::generate_run(g, spec));
  }
  return runs;
}

}  // namespace rig::testing
