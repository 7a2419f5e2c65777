#pragma once
// Diagnose: which physical effect is the model most likely missing? For every applicable
// candidate, fit baseline + candidate and measure its cross-validated gain. A candidate is
// significant only if it (1) lowers the CV RMSE by at least 2 %, (2) helps in at least 60 %
// of the held-out runs, and (3) wins by an information criterion whose sample count is
// the autocorrelation-corrected effective number of samples (1 kHz samples are not
// independent: N_eff = sum n (1 - rho) / (1 + rho), rho the lag-1 autocorrelation of the
// candidate's CV residuals).
//
// The verdict: a significant candidate is named only if it brings the CV error close to
// the floor (within floor + 30 % of the baseline's excess, or not well above the floor);
// when structure well above the floor remains it is "unexplained", with where the excess
// lies and the best partial candidate; "none" only when the baseline is near the floor.
// The floor is the real one: measurement noise plus what eye-to-eye variation (tissue scale,
// puncture depth; see eye_variation.hpp) adds to a prediction for an eye not yet seen.
#include <string>
#include <vector>

#include "cross_validation.hpp"
#include "force_model.hpp"
#include "residual_structure.hpp"
#include "run_data.hpp"

namespace rig::model {

struct CandidateResult {
  std::string effect;
  bool applicable = true;
  std::string not_applicable;  // why, if not
  double cv_rmse_N = 0.0;
  double gain_pct = 0.0;
  double runs_improved = 0.0;  // fraction of held-out runs it helped
  // The within-eye channel (cross_validation.hpp): each held-out run with its own eye.
  double own_eye_cv_rmse_N = 0.0;
  double own_eye_gain_pct = 0.0;
  double own_eye_runs_improved = 0.0;
  std::string channel;         // where it is significant: population | own eye | both | ""
  double rank_gain_pct = 0.0;  // its gain on the channel it is significant in (the larger), less up
                               // to 10 points the other channel lost; ranks significant ones
  double delta_bic = 0.0;      // with the effective sample count; < 0 favours the candidate
  double n_effective = 0.0;
  bool significant = false;
  double floor_N = 0.0;        // the floor of baseline + this candidate (its own eye spread)
  double explained_pct = 0.0;  // share of the baseline's excess over that floor it removes
  bool converged = true;       // its fit on all runs converged
  bool left_start = true;      // its fit moved from the start values
  std::string evidence;
  std::string where;  // phase where the error fell most
};

// The floor of a model family on a run set: sqrt(measurement^2 + eye variation^2).
struct NoiseFloor {
  double total_N = 0.0;
  double measurement_N = 0.0;    // white noise of the force channel (MAD of second differences)
  double eye_variation_N = 0.0;  // RMS that unseen eyes' scale and puncture shift add
  EyeSpread eye_spread;          // population SDs of the eye parameters
};

struct Diagnosis {
  double baseline_cv_rmse_N = 0.0;
  double baseline_own_eye_cv_rmse_N = 0.0;  // within-eye channel; its floor is floor.measurement_N
  // The floor of the model the verdict leaves: baseline + the named effect, else the
  // baseline (an effect that varies from run to run - IOP, velocity, wear - looks like eye
  // variation to the baseline and inflates its floor).
  double noise_floor_N = 0.0;
  NoiseFloor floor;
  std::vector<std::string> base_effects;    // already in the model
  std::vector<CandidateResult> candidates;  // best first; inapplicable ones last
  std::string verdict = "none";             // none | EFFECT | covariate:KEY | unexplained
  std::string partial_candidate;            // with "unexplained": the best candidate, if any helps
  ResidualStructure unexplained_where;      // with "unexplained": where the excess lies
  std::vector<std::string> warnings;
};

struct DiagnoseOptions {
  std::vector<std::string> with;  // effects to treat as part of the baseline (iterating)
  std::vector<std::string> only;  // restrict the candidates (empty = whole catalogue)
  int threads = 2;
};

Diagnosis diagnose(const ForceModel& model, const std::vector<RunData>& runs,
                   const DiagnoseOptions& options = {});

// Pooled white-noise level of the force channel over the runs' analysed samples [N].
double noise_floor(const std::vector<const PreparedRun*>& runs);

class ModelFamily;
// The floor of a fitted family: measurement noise and what its eye spread adds.
NoiseFloor floor_of(const ModelFamily& family, const FitResult& full,
                    const std::vector<const PreparedRun*>& runs);

}  // namespace rig::model
