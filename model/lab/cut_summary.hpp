#pragma once
// The figures a technician wants after a cut: how many samples, how well the velocity was
// held during the insertion, where the puncture peak was, and how far the model is off.
#include <cstddef>
#include <optional>

#include "force_model.hpp"
#include "run_data.hpp"

namespace rig::model {

struct CutSummary {
  std::size_t samples = 0;
  double commanded_velocity_mm_s = 0.0;
  double velocity_mm_s = 0.0;  // median slope of x(t) over 0.2 s spans of the insertion
  double velocity_error_pct = 0.0;
  double longest_gap_ms = 0.0;  // longest time between two samples of the insertion (a stall)
  double peak_force_N = 0.0;    // puncture peak (largest force before x_pf)
  double x_at_peak_mm = 0.0;
  double max_depth_mm = 0.0;
  std::optional<double> model_rmse_N;  // insertion, against the model at the run's IOP
};

// Throws std::invalid_argument naming the run if it has no insertion.
CutSummary summarize_cut(const RunData& run, const ForceModel* model);

}  // namespace rig::model
