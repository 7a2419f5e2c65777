#pragma once
// Diagnose: which physical effect is the model most likely missing? For every applicable
// candidate, fit baseline + candidate and measure its cross-validated gain. A candidate is
// significant only if it (1) lowers the CV RMSE by at least 2 %, (2) helps in at least 60 %
// of the held-out runs, and (3) wins by an information criterion whose sample count is
// the autocorrelation-corrected effective number of samples (1 kHz samples are not
// independent: N_eff = sum n (1 - rho) / (1 + rho), rho the lag-1 autocorrelation of the
// candidate's CV residuals). Otherwise the verdict is "none".
#include <string>
#include <vector>

#include "cross_validation.hpp"
#include "force_model.hpp"
#include "run_data.hpp"

namespace rig::model {

struct CandidateResult {
  std::string effect;
  bool applicable = true;
  std::string not_applicable;  // why, if not
  double cv_rmse_N = 0.0;
  double gain_pct = 0.0;
  double runs_improved = 0.0;  // fraction of held-out runs it helped
  double delta_bic = 0.0;      // with the effective sample count; < 0 favours the candidate
  double n_effective = 0.0;
  bool significant = false;
  std::string evidence;
  std::string where;           // phase where the error fell most
};

struct Diagnosis {
  double baseline_cv_rmse_N = 0.0;
  double noise_floor_N = 0.0;
  std::vector<std::string> base_effects;     // already in the model
  std::vector<CandidateResult> candidates;   // best first; inapplicable ones last
  std::string verdict = "none";
  std::vector<std::string> warnings;
};

struct DiagnoseOptions {
  std::vector<std::string> with;  // effects to treat as part of the baseline (iterating)
  std::vector<std::string> only;  // restrict the candidates (empty = whole catalogue)
  int threads = 2;
};

Diagnosis diagnose(const ForceModel& model, const std::vector<RunData>& runs, const DiagnoseOptions& options = {});

// Pooled white-noise level of the force channel over the runs' analysed samples [N].
double noise_floor(const std::vector<const PreparedRun*>& runs);

}  // namespace rig::model
