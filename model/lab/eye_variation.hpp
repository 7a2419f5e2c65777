#pragma once
// Eyes differ: each run gets its own tissue-force scales (before and after the puncture) and
// puncture-depth shift (random effects), estimated with shrinkage toward the population
// (empirical Bayes):
//   1. per run, the unpenalised estimate d_r and its sampling variance v_r (scales: least
//      squares over the run's fit rows; puncture shift: grid + golden search on the rows
//      around the model's puncture, variance from the curvature of that error profile);
//   2. the population variance by the method of moments, tau^2 = max(0, sum d_r^2 / (n - p)
//      - mean v_r), p the parameters fitted on one value per eye (`fitted`: the level and any
//      law in the run's velocity, IOP or a covariate; EyeDof);
//   3. each run's value shrunk toward the population, d_r tau^2 / (tau^2 + v_r).
// Eye-free data give tau = 0 and every eye exactly the population model.
#include <Eigen/Core>

#include <vector>

#include "eye_params.hpp"
#include "predictor.hpp"

namespace rig::model {

struct EyeEstimate {
  std::vector<EyeParams> eyes;  // per run, shrunk
  EyeSpread spread;             // population standard deviations
};

// One eye parameter's population variance tau^2 by the method of moments (step 2): from each
// eye's unpenalised deviation d_r from the population model and its sampling variance v_r,
// after `fitted` parameters were fitted on one value per eye: max(0, sum d_r^2 / (n - fitted)
// - mean v_r), n - fitted at least 1.
double eye_parameter_variance(const std::vector<double>& deviations,
                              const std::vector<double>& variances, int fitted);

// Eye parameters of `runs` given the shared parameters and each run's instrument
// coefficients (`betas`, aligned with runs; empty vectors if none). Needs >= 3 runs to
// estimate a spread; with fewer every eye is the population model. `fitted`: the degrees of
// freedom the shared parameters took from each eye parameter (step 2).
EyeEstimate estimate_eyes(const Predictor& predictor, const std::vector<const PreparedRun*>& runs,
                          const ModelParams& p, const std::vector<Eigen::VectorXd>& betas,
                          const EyeDof& fitted);

// The mean squared error per analysed sample [N^2] that eye variation adds to a prediction
// made with the population model (eye parameters unknown): the expectation over eyes drawn
// from `spread` (3-point Gauss-Hermite in the puncture shift, exact in the scales) of
// (prediction of that eye - population prediction)^2, averaged over the runs' fit rows and
// weighted by each run's analysed sample count.
// One run's own eye, unpenalised (no population to shrink toward): its tissue-force scales
// and puncture shift fitted to its own fit rows, given the shared parameters and its
// instrument coefficients `beta` (empty if none). For the within-eye CV channel.
EyeParams own_eye(const Predictor& predictor, const PreparedRun& run, const ModelParams& p,
                  const Eigen::VectorXd& beta);

// Each run's own puncture shift, unpenalised (step 1: no population to shrink toward) [mm],
// and its sampling variance [mm^2] (infinite where the run says nothing of its depth), given
// the shared parameters and the instrument coefficients `betas` (aligned with runs; empty
// vectors if none). For a law of the puncture depth fitted on the eyes (puncture_law.hpp).
struct OwnShift {
  double shift_mm = 0.0;
  double variance_mm2 = 0.0;
};
std::vector<OwnShift> own_puncture_shifts(const Predictor& predictor,
                                          const std::vector<const PreparedRun*>& runs,
                                          const ModelParams& p,
                                          const std::vector<Eigen::VectorXd>& betas);

double eye_variance_N2(const Predictor& predictor, const std::vector<const PreparedRun*>& runs,
                       const ModelParams& p, const EyeSpread& spread);

}  // namespace rig::model
