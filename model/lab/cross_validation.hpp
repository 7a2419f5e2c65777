#pragma once
// Cross-validated error of a model family on runs. Shared parameters are fitted on the
// training runs and judged on held-out runs (leave-runs-out, up to 5 folds); per-run
// coefficients of instrument effects are fitted on the held-out run's own data by blocked
// CV inside the run (5 contiguous time blocks), so they never see the samples they predict.
// With a single run, the folds are time blocks of that run.
//
// Honesty: nothing of a held-out run reaches the fit of its fold. Each fold's model comes
// from `model_for(training runs)`: its predictor (the form of every effect family chosen on
// the training runs only, covariates standardised on them) and its start values (including
// the grids of multimodal terms, scored on the training runs). The fold is fitted from there
// (no warm start from the fit on all runs), and the eyes of held-out runs are the population
// model's (their own scale and puncture shift are never fitted).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "fitter.hpp"
#include "predictor.hpp"

namespace rig::model {

struct CvResult {
  double rmse_N = 0.0;
  std::vector<double> run_sse;
  std::vector<std::size_t> run_n;
  std::vector<double> run_rho;                 // lag-1 autocorrelation of the CV residuals
  std::vector<std::vector<double>> residuals;  // per run, over its analysed samples
  double own_eye_rmse_N = 0.0;  // the within-eye channel (multi-run CV only, else = rmse_N)
  std::vector<double> own_eye_run_sse;
  std::vector<double> own_eye_run_rho;
  FitResult full;                // the fit on all runs
  std::vector<FitResult> folds;  // each fold's fit on its training runs
  std::vector<std::string>
      full_forms;  // each term's form in the fit on all runs ("" if it has none)
  std::vector<std::vector<std::string>>
      fold_forms;  // per fold: each term's form, chosen on its training runs
};

// The model one fit uses (a fold's, or the one on all runs): a predictor whose effect
// families are in the forms chosen on exactly the runs it is fitted on, and start values
// picked on those runs. `predictor` may share ownership of the terms it evaluates.
struct TrainedModel {
  std::shared_ptr<const Predictor> predictor;
  ModelParams start;
  std::vector<std::string> forms;  // each term's form, in term order ("" if it has none)
};
using TrainedModelFor =
    std::function<TrainedModel(const std::vector<const PreparedRun*>& training_runs)>;

CvResult cross_validate(const std::vector<const PreparedRun*>& runs,
                        const TrainedModelFor& model_for, int max_folds = 5);

// Residuals of a held-out run: shared parameters given, per-run coefficients by blocked CV.
// `eye` null: the population model (an unseen eye).
std::vector<double> held_out_residuals(const Predictor& predictor, const PreparedRun& run,
                                       const ModelParams& params, const EyeParams* eye = nullptr);

}  // namespace rig::model
