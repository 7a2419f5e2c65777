#pragma once
// The series the HTML report and the page's Model lab tab plot, computed once here so both
// show the same thing: the signed residual (measured - model, not only its RMSE) against
// depth, split into insertion and retraction (hysteresis shows as the two curves parting),
// against time in the hold, and per-run small multiples of measured and model force. With a
// second comparison (after a fit) every series carries the "after" values beside "before".
#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

#include "comparison.hpp"
#include "run_data.hpp"

namespace rig::model {

struct SeriesLimits {
  std::size_t depth_bins = 120;      // bins over the deepest insertion
  std::size_t runs_shown = 24;       // small multiples
  std::size_t points_per_run = 400;  // per small multiple and per hold trace
};

// `after` may be null. Both comparisons must be of `runs`, in the same order.
nlohmann::json report_series(const std::vector<RunData>& runs, const Comparison& before,
                             const Comparison* after, const SeriesLimits& limits = {});

}  // namespace rig::model
