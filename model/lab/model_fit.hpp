#pragma once
// `rig model fit`: refit the model family across runs (and, on request, per run) with the
// added effects; report the cross-validated error before and after, per phase, and the
// fitted model, ready to be saved as a model file for the overlay and the haptics.
#include <map>
#include <string>
#include <vector>

#include "eye_params.hpp"
#include "force_model.hpp"
#include "run_data.hpp"
#include "segment_metrics.hpp"

namespace rig::model {

struct RunFit {
  std::string label;
  double rmse_N = 0.0;
  std::map<std::string, double> params;  // Eq. 1 parameters fitted to this run alone
};

struct FitReport {
  std::vector<std::string> effects;  // every effect of the fitted family
  double before_cv_rmse_N = 0.0;
  double after_cv_rmse_N = 0.0;
  double noise_floor_N = 0.0;  // of the fitted family: measurement + eye variation
  double measurement_noise_N = 0.0;
  double eye_variation_N = 0.0;
  EyeSpread eye_spread;                         // population SDs of the eye parameters
  std::vector<SegmentMetrics> before_by_phase;  // from the cross-validated residuals
  std::vector<SegmentMetrics> after_by_phase;
  std::map<std::string, std::map<std::string, double>> params;  // "baseline" and each effect
  std::vector<RunFit> per_run;
  ForceModel fitted;
  std::vector<std::string> warnings;
};

FitReport fit_model(const ForceModel& model, const std::vector<RunData>& runs,
                    const std::vector<std::string>& add, bool per_run = false);

}  // namespace rig::model
