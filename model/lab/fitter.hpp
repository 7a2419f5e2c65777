#pragma once
// Fits the model family to a set of runs: Levenberg-Marquardt (Eigen) over the shared
// parameters - Eq. 1's and the added effects' - with the per-run linear coefficients of the
// instrument effects solved inside every evaluation (variable projection). Bounds are kept
// by a smooth sine transform of each bounded parameter. With three runs or more, each run
// is also its own eye (a tissue-force scale and a puncture shift, shrunk toward the
// population, see eye_variation.hpp), refitted alternately with the shared parameters.
#include <Eigen/Core>

#include <string>
#include <vector>

#include "eye_variation.hpp"
#include "predictor.hpp"

namespace rig::model {

struct FitResult {
  ModelParams params;
  std::vector<Eigen::VectorXd> run_coefficients;  // per run: its instrument coefficients
  std::vector<EyeParams> eyes;                    // per run (all zero: eyes do not differ)
  EyeSpread eye_spread;                           // population spread of the eye parameters
  double rmse_N = 0.0;                            // on the fit rows, each run with its eye
  int evaluations = 0;
  bool converged = false;
  bool left_start = false;                        // some shared parameter moved from its start
  std::vector<std::vector<double>> start_shared;  // the effect terms' start values, per term
};

struct BaselineParam {
  const char* name;
  const char* unit;
  double ContinuousParams::*member;
  double lower;
  double upper;
};
const std::vector<BaselineParam>& baseline_parameters();

// Evaluations of the short fit that scores one start of a term that fits each start
// (EffectTerm::fit_each_start): enough to reach the start's valley, a third of a full fit.
inline constexpr int kStartProbeEvaluations = 100;
// Runs below which no law of the puncture depth is placed (a level and two slopes need a
// fourth run to leave the eyes a spread).
inline constexpr std::size_t kMinLawRuns = 4;

class Fitter {
 public:
  Fitter(const Predictor& predictor, std::vector<const PreparedRun*> runs, bool fit_baseline = true,
         bool eyes_differ = true);
  FitResult fit(const ModelParams& start, int max_evaluations = 300) const;

  // Residuals (measured - predicted) of a run at `rows`, with its linear coefficients
  // solved on `coefficient_rows` (the same rows, or other blocks for blocked CV).
  static std::vector<double> residuals(const Predictor& predictor, const PreparedRun& run,
                                       const ModelParams& p, const std::vector<std::size_t>& rows,
                                       Eigen::VectorXd* coefficients = nullptr,
                                       const EyeParams* eye = nullptr);

  std::size_t parameter_count() const { return specs_.size(); }
  // Sum of squared residuals at the fit rows, every linear coefficient solved [N^2].
  double sse(const ModelParams& p) const;

 private:
  // Degrees of freedom the fitted shared parameters take from each eye parameter's spread.
  EyeDof eye_level_params(const ModelParams& p) const;
  struct Spec {
    double lower, upper;
    bool bounded;
  };
  // Residuals of all runs at their fit rows (into fvec if given): shared linear coefficients
  // (gamma) and per-run ones (betas) solved jointly by alternating least squares.
  void evaluate_all(const ModelParams& p, const std::vector<EyeParams>& eyes, Eigen::VectorXd* fvec,
                    Eigen::VectorXd& gamma, std::vector<Eigen::VectorXd>& betas) const;
  // The first fit, eyes at the population: with a law of the puncture depth in the terms,
  // placed from the eyes' own shifts first (puncture_law.hpp).
  FitResult population_fit(const ModelParams& start, int max_evaluations) const;
  // Levenberg-Marquardt over the shared parameters, the eyes held.
  FitResult minimise(const ModelParams& start, const std::vector<EyeParams>& eyes,
                     int max_evaluations) const;
  ModelParams unpack(const Eigen::VectorXd& u, const ModelParams& start) const;
  Eigen::VectorXd pack(const ModelParams& p) const;
  friend struct FitFunctor;

  const Predictor* predictor_;
  std::vector<const PreparedRun*> runs_;
  bool fit_baseline_;
  bool eyes_differ_;
  std::vector<Spec> specs_;
  std::size_t rows_ = 0;
};

}  // namespace rig::model
