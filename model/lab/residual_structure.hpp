#pragma once
// Where cross-validated residuals stand above the noise floor: the bin of each view (phase,
// direction of travel, depth band, time in hold) that holds most of the excess squared
// error (sum e^2 - n floor^2), and the run covariate that best tracks the runs' mean
// residual. Tells an `unexplained` verdict where to look.
#include <string>
#include <vector>

#include "prepared_run.hpp"

namespace rig::model {

struct ExcessBin {
  std::string view;            // "phase", "direction", "depth_mm", "hold_s"
  std::string bin;             // e.g. "retraction", "retracting", "4-5", "0.5-2"
  double share = 0.0;          // of the total excess squared error (0..1)
  double mean_residual_N = 0;  // signed: > 0 the model predicts too little force there
};

struct ResidualStructure {
  std::vector<ExcessBin> bins;  // the leading bin of every view, largest share first
  std::string covariate;        // the run covariate best correlated with the runs' mean residual
  double covariate_correlation = 0.0;
  double covariate_threshold = 1.0;  // |correlation| worth quoting for this many runs
  std::string summary() const;       // one line for people
};

// `residuals[r][k]` belongs to runs[r]->analysed[k]; `covariates` are the keys to try.
ResidualStructure locate_excess(const std::vector<const PreparedRun*>& runs,
                                const std::vector<std::vector<double>>& residuals, double floor_N,
                                const std::vector<std::string>& covariates);

}  // namespace rig::model
