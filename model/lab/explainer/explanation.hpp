#pragma once
// What the explainer proposes for structure the model's residuals still carry: a closed-form
// user term (muParser, in the user-term variables) with its coefficients as named
// parameters, the phase it applies in, and how much cross-validated error it removes -
// predicted by the sparse regression, then measured by fitting the model with the term.
#include <string>
#include <utility>
#include <vector>

#include "force_model.hpp"

namespace rig::model::explainer {

struct ExplainOptions {
  std::vector<std::string> with;        // effects the baseline has besides the model file's own
  std::string term_name = "explained";  // taken if free, else explained_2, ...
  int max_features = 4;                 // a readable closed form
  std::size_t rows_per_run = 1500;      // evenly spaced samples per run for the regression
  bool validate = true;                 // fit the model with the term and cross-validate it
};

struct ExplainedFeature {
  std::string parameter;        // c1, c2, ... in the term's expression
  std::string expression;       // the feature, e.g. "x^2"
  std::string gate;             // the phase it is confined to (all, insertion, precut, ...)
  double coefficient = 0.0;     // from the regression [N per unit of the feature]
  double contribution_N = 0.0;  // RMS of coefficient x feature over all samples analysed
};

struct Explanation {
  bool proposed = false;  // the term is worth adding: it lowers the CV error enough
  std::string summary;    // in words: what was found, or why nothing is proposed
  UserTerm term;          // the proposal; params hold the regression's values (start values)
  std::vector<ExplainedFeature> features;  // largest contribution first
  std::string where;                       // phase(s) and features, e.g. "retraction: x^2"
  std::vector<std::string> base_effects;
  double baseline_cv_rmse_N = 0.0;
  double noise_floor_N = 0.0;
  double predicted_cv_rmse_N = 0.0;  // the regression's held-out error (sampled rows)
  double predicted_gain_pct = 0.0;   // against the baseline on the same rows
  double runs_improved = 0.0;        // fraction of held-out runs the regression helped
  bool validated = false;            // the model was fitted and cross-validated with the term
  double after_cv_rmse_N = 0.0;      // CV RMSE of baseline + term (every sample)
  double after_gain_pct = 0.0;
  double after_runs_improved = 0.0;
  UserTerm fitted;                                   // the term with the parameters of that fit
  std::size_t library_size = 0;                      // candidate features offered to the selection
  std::vector<std::pair<std::size_t, double>> path;  // features -> held-out RMSE, along the path
  std::vector<std::string> warnings;
};

}  // namespace rig::model::explainer
