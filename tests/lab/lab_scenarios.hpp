#pragma once
// Datasets of simulated runs with hidden effects, for the model lab's tests.
#include <stdexcept>
#include <string>
#include <vector>

#include "run_generator.hpp"

namespace rig::testing {

// 9 runs: IOP 15/16.5/18 mmHg x 1.5/2.5/3.5 mm/s, post-mortem 0.5..3.5 h, eyes varying;
// every run, whatever the hidden effect, uses the one protocol of apply_standard_protocol
// (12 mm deep, stops before and after the puncture, a hold at depth), so that no protocol
// gives the answer away. `holds` is kept for old callers: every run has its holds now.
// The generator with these hidden effects ("name[:form][=size]"); throws on a bad spec.
inline sim::GeneratorOptions generator_with(const std::vector<std::string>& hidden) {
  sim::GeneratorOptions g;
  for (const auto& spec : hidden) {
    std::string error;
    const auto effect = sim::parse_hidden_effect(spec, error);
    if (!effect) throw std::invalid_argument(error);
    g.effects.push_back(*effect);
  }
  return g;
}

inline std::vector<model::RunData> scenario_runs(const std::vector<std::string>& hidden,
                                                 std::uint64_t seed = 3, bool /*holds*/ = true) {
  const sim::GeneratorOptions g = generator_with(hidden);
  std::vector<model::RunData> runs;
  for (const auto& spec :
       sim::design_runs({15, 16.5, 18}, {1.5, 2.5, 3.5},
                        {0.5, 2.0, 3.5, 1.0, 3.0, 2.5, 1.5, 0.8, 3.2}, 12.0, 1.0, seed)) {
    sim::RunSpec standard = spec;
    sim::apply_standard_protocol(standard);
    runs.push_back(sim::generate_run(g, standard));
  }
  return runs;
}

// For tests of a mechanism (the explainer, user terms) on controlled data: the same 9 runs,
// 12 mm deep without stops, identical eyes — the conditions those mechanisms are specified
// for. Robustness to protocols and eyes is what scenario_runs and the blind zoo measure.
inline std::vector<model::RunData> mechanism_runs(const std::vector<std::string>& hidden,
                                                  std::uint64_t seed = 3) {
  sim::GeneratorOptions g = generator_with(hidden);
  g.physics.tissue.eye_variability = 0.0;
  std::vector<model::RunData> runs;
  for (const auto& spec :
       sim::design_runs({15, 16.5, 18}, {1.5, 2.5, 3.5},
                        {0.5, 2.0, 3.5, 1.0, 3.0, 2.5, 1.5, 0.8, 3.2}, 12.0, 0.0, seed)) {
    runs.push_back(sim::generate_run(g, spec));
  }
  return runs;
}

}  // namespace rig::testing
