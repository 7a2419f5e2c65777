#pragma once
// A law of the puncture depth in numbers fixed per run (a covariate's "moves the puncture"
// form: x_pi + xpi_1 z + xpi_2 z^2 [mm]), placed from the eyes' own puncture shifts before
// the eyes' spread is estimated. Between fit rows the error is flat in the law's slopes, so
// the fit alone leaves them where they start; the eyes' shifts then take up what the law
// misses, and the candidate's floor becomes the eyes' (blind draws 160009, 170031).
//
// The placement: each run's unpenalised puncture shift d_r with its sampling variance v_r
// (eye_variation.hpp, step 1) is regressed on the run's regressors (and a level, folded into
// the model's puncture shift) by generalised least squares, weights 1/(tau^2 + v_r), tau^2
// the eyes' own spread by the method of moments on the regression's residuals, iterated until
// tau^2 settles. The law moves every run's depth by its prediction; the shifts are measured
// again under it (they are searched within +-0.6 mm of the model's puncture) until no run's
// depth moves by more than kLawTolerance_mm. The eyes keep only their own shift.
#include <Eigen/Core>

#include <vector>

#include "predictor.hpp"

namespace rig::model {

inline constexpr double kLawTolerance_mm =
    0.01;  // a round that moves no depth more than this ends the placement
inline constexpr int kLawMaxRounds = 8;

// The weighted regression of the shifts on X (one row per run; rows with an infinite or
// non-positive variance are left out).
struct ShiftRegression {
  Eigen::VectorXd coefficients;  // per column of X [mm per unit of that regressor]
  double tau2_mm2 = 0.0;         // the eyes' own spread left by the law [mm^2]
  int runs = 0;                  // runs with a finite variance (the regression's rows)
  bool solved = false;           // enough runs: more than columns
};
ShiftRegression regress_shifts(const std::vector<double>& shifts_mm,
                               const std::vector<double>& variances_mm2, const Eigen::MatrixXd& X);

struct PlacedLaw {
  bool placed = false;
  int rounds = 0;
  double last_move_mm = 0.0;  // the largest change of a run's depth in the last round [mm]
  double tau_mm = 0.0;        // the eyes' own spread the last regression left [mm]
};

// Whether some term of `predictor` sets the puncture depth by a law
// (EffectTerm::puncture_regressors).
bool has_puncture_law(const Predictor& predictor, const std::vector<const PreparedRun*>& runs);

// Places the law in `p`: the terms' puncture coefficients and, with `level`, the model's own
// puncture shift (p.base.x_pi_shift), each held inside its bounds. `betas`: the runs'
// instrument coefficients (aligned with runs; empty if none are known yet).
PlacedLaw place_puncture_law(const Predictor& predictor,
                             const std::vector<const PreparedRun*>& runs, ModelParams& p,
                             const std::vector<Eigen::VectorXd>& betas, bool level);

}  // namespace rig::model
