#pragma once
// Effects outside the lab's catalogue, added to the force channel of simulated runs, for the
// explainer's tests: what a real rig could show that no catalogue term names.
#include <algorithm>
#include <string>
#include <vector>

#include "run_data.hpp"

namespace rig::testing {

// Index of the deepest sample: insertion before it, (hold and) retraction after it.
inline std::size_t deepest_sample(const model::RunData& run) {
  return static_cast<std::size_t>(std::max_element(run.x_mm.begin(), run.x_mm.end()) -
                                  run.x_mm.begin());
}

// A force k x^2 [N, x in mm] only while the blade is withdrawn (e.g. a lip dragged back out).
inline void add_retraction_square(std::vector<model::RunData>& runs, double k_N_per_mm2) {
  for (model::RunData& run : runs) {
    for (std::size_t i = deepest_sample(run) + 1; i < run.size(); ++i) {
      if (run.x_mm[i] > 0.0) run.force_N[i] += k_N_per_mm2 * run.x_mm[i] * run.x_mm[i];
    }
  }
}

// Blade wear: run k of the session is the blade's k-th use (metadata blade_uses) and the
// force grows by k_N * uses * x while inserting [N, x in mm].
inline void add_blade_wear(std::vector<model::RunData>& runs, double k_N_per_use_mm) {
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const auto uses =
        static_cast<double>((r * 4) % runs.size());  // session order, not the design's order
    runs[r].set("blade_uses", std::to_string(static_cast<int>(uses)));
    const std::size_t deepest = deepest_sample(runs[r]);
    for (std::size_t i = 0; i <= deepest; ++i) {
      if (runs[r].x_mm[i] > 0.0) runs[r].force_N[i] += k_N_per_use_mm * uses * runs[r].x_mm[i];
    }
  }
}

}  // namespace rig::testing
