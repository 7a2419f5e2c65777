#pragma once
// The model's prediction for a run: Eq. 1 (continuous reading) with the added effects, in
// stages - per-run model parameters, displacement correction, force scaling, additive
// forces - and the per-run linear columns of the instrument effects.
//
//   F = [insertion or hold] Eq1(x - sum x_shift; params adjusted per run, IOP) * prod scale
//       + sum add(...) + sum_k beta_run,k X_k          (retraction and approach: Eq1 = 0)
#include <Eigen/Core>

#include <vector>

#include "effect_term.hpp"
#include "eye_params.hpp"
#include "force_model.hpp"
#include "prepared_run.hpp"

namespace rig::model {

struct ModelParams {
  ContinuousParams base;
  std::vector<std::vector<double>> shared;  // per effect term, in term order
  Eigen::VectorXd shared_linear;            // coefficients of the shared linear columns (solved)
};

class Predictor {
 public:
  Predictor(const ForceModel& model, std::vector<const EffectTerm*> terms);

  // Prediction without the linear parts at `rows`; fills X with the per-run linear columns
  // and S with the shared linear columns when given. `eye` (null: the population model)
  // scales the tissue force and shifts the puncture; `tissue` receives the tissue force
  // before the eye's scales, split by where each acts.
  void evaluate(const PreparedRun& run, const ModelParams& p, const std::vector<std::size_t>& rows,
                std::vector<double>& out, Eigen::MatrixXd* X = nullptr,
                Eigen::MatrixXd* S = nullptr, const EyeParams* eye = nullptr,
                EyeColumns* tissue = nullptr) const;
  int linear_columns() const { return linear_columns_; }
  int shared_columns() const { return shared_columns_; }
  const std::vector<const EffectTerm*>& terms() const { return terms_; }
  const ForceModel& model() const { return model_; }
  ModelParams initial_params() const;

 private:
  void write_design(const SampleView& s, const ModelParams& p, std::size_t n, Eigen::MatrixXd* X,
                    Eigen::MatrixXd* S, double* row) const;
  ForceModel model_;
  std::vector<const EffectTerm*> terms_;
  int linear_columns_ = 0;  // per run
  int shared_columns_ = 0;
};

// The per-run linear coefficients that best explain `residual` with columns X (least
// squares, QR); a small ridge keeps ill-posed columns (too few cycles) harmless.
Eigen::VectorXd solve_linear(const Eigen::MatrixXd& X, const Eigen::VectorXd& residual);

}  // namespace rig::model
