#include "cross_validation.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>

#include "eye_variation.hpp"

namespace rig::model {
namespace {

constexpr int kBlocks = 5;

double lag1(const std::vector<double>& r) {
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    den += r[i] * r[i];
    if (i > 0) num += r[i] * r[i - 1];
  }
  return den > 0.0 ? std::clamp(num / den, 0.0, 0.99) : 0.0;
}

double sum_of_squares(const std::vector<double>& r) {
  double sse = 0.0;
  for (const double e : r) sse += e * e;
  return sse;
}

void add_run(CvResult& out, std::vector<double> residual) {
  out.run_sse.push_back(sum_of_squares(residual));
  out.run_n.push_back(residual.size());
  out.run_rho.push_back(lag1(residual));
  out.residuals.push_back(std::move(residual));
}

double pooled_rmse(const std::vector<double>& run_sse, const std::vector<std::size_t>& run_n) {
  double sse = 0.0;
  std::size_t n = 0;
  for (std::size_t r = 0; r < run_sse.size() && r < run_n.size(); ++r)
    sse += run_sse[r], n += run_n[r];
  return n > 0 ? std::sqrt(sse / static_cast<double>(n)) : 0.0;
}

void finish(CvResult& out) {
  out.rmse_N = pooled_rmse(out.run_sse, out.run_n);
  if (out.own_eye_run_sse.empty()) {  // one run: no eyes to tell apart, both channels are one
    out.own_eye_run_sse = out.run_sse;
    out.own_eye_run_rho = out.run_rho;
  }
  out.own_eye_rmse_N = pooled_rmse(out.own_eye_run_sse, out.run_n);
}

// The held-out run's residuals with its own eye (the within-eye channel).
std::vector<double> own_eye_residuals(const Predictor& predictor, const PreparedRun& run,
                                      const ModelParams& params) {
  Eigen::VectorXd beta;
  if (predictor.linear_columns() > 0)
    Fitter::residuals(predictor, run, params, run.fit_rows, &beta);
  const EyeParams eye = own_eye(predictor, run, params, beta);
  return held_out_residuals(predictor, run, params, &eye);
}

std::size_t block_of(std::size_t k, std::size_t n) {
  return std::min<std::size_t>(kBlocks - 1, k * kBlocks / std::max<std::size_t>(n, 1));
}

// A run's offset steps are found on all its samples, with its phases (level_shifts.hpp). A
// held-out block must be predicted without its own samples, and all the other blocks tell of
// a step inside it is that the zero moved somewhere between them: so, to predict the block,
// a step found in [from_s, to_s] is put at the middle of that span. Empty if none is there.
std::optional<PreparedRun> steps_blinded(const PreparedRun& run, double from_s, double to_s) {
  const auto& steps = run.seg.offset_steps;
  const bool inside = std::any_of(steps.begin(), steps.end(), [&](const OffsetStep& s) {
    return s.t_s >= from_s && s.t_s <= to_s;
  });
  if (!inside) return std::nullopt;
  PreparedRun blinded = run;
  for (OffsetStep& s : blinded.seg.offset_steps) {
    if (s.t_s >= from_s && s.t_s <= to_s) s.t_s = 0.5 * (from_s + to_s);
  }
  return blinded;
}

// One time block of a run held out: the residuals of its samples (rows `test`, in order) for
// a fit on the other blocks; per-run coefficients are those of the training blocks.
void block_residuals(const Predictor& predictor, const PreparedRun& run, const PreparedRun& train,
                     const ModelParams& params, const std::vector<std::size_t>& test,
                     std::vector<double>& out) {
  Eigen::VectorXd beta;
  Fitter::residuals(predictor, train, params, train.fit_rows, &beta);
  std::vector<double> prediction;
  Eigen::MatrixXd X;
  predictor.evaluate(run, params, test, prediction, predictor.linear_columns() > 0 ? &X : nullptr);
  out.resize(test.size());
  for (std::size_t n = 0; n < test.size(); ++n) {
    double r = run.data->force_N[test[n]] - prediction[n];
    if (beta.size() > 0) r -= X.row(static_cast<Eigen::Index>(n)).dot(beta);
    out[n] = r;
  }
}

// One run, no other runs to learn from: folds are time blocks of the run itself. Each fold's
// model (forms, start values) is chosen on a copy of the run whose fit rows are the other
// blocks' samples.
CvResult within_run(const PreparedRun& run, const TrainedModelFor& model_for) {
  CvResult out;
  const TrainedModel full = model_for({&run});
  out.full = Fitter(*full.predictor, {&run}).fit(full.start);
  out.full_forms = full.forms;
  std::vector<double> residual(run.analysed.size());
  for (std::size_t b = 0; b < kBlocks; ++b) {
    PreparedRun train = run;
    train.fit_rows.clear();
    std::vector<std::size_t> test, test_at;
    for (std::size_t k = 0; k < run.analysed.size(); ++k) {
      const bool held_out = block_of(k, run.analysed.size()) == b;
      (held_out ? test : train.fit_rows).push_back(run.analysed[k]);
      if (held_out) test_at.push_back(k);
    }
    if (!test.empty()) {
      if (auto blinded =
              steps_blinded(train, run.data->t_s[test.front()], run.data->t_s[test.back()]))
        train = std::move(*blinded);
    }
    pack_fit_rows(train);
    const TrainedModel fold = model_for({&train});
    out.folds.push_back(Fitter(*fold.predictor, {&train}).fit(fold.start));
    out.fold_forms.push_back(fold.forms);
    std::vector<double> block;
    block_residuals(*fold.predictor, train, train, out.folds.back().params, test,
                    block);  // train: the run as its other blocks know it
    for (std::size_t n = 0; n < test_at.size(); ++n) residual[test_at[n]] = block[n];
  }
  add_run(out, std::move(residual));
  finish(out);
  return out;
}

}  // namespace

std::vector<double> held_out_residuals(const Predictor& predictor, const PreparedRun& run,
                                       const ModelParams& params, const EyeParams* eye) {
  std::vector<double> prediction;
  Eigen::MatrixXd Xall;
  const bool linear = predictor.linear_columns() > 0;
  predictor.evaluate(run, params, run.analysed, prediction, linear ? &Xall : nullptr, nullptr, eye);
  const std::size_t n = run.analysed.size();
  std::vector<double> residual(n);
  for (std::size_t k = 0; k < n; ++k)
    residual[k] = run.data->force_N[run.analysed[k]] - prediction[k];
  if (!linear) return residual;
  const Eigen::Map<const Eigen::VectorXd> r(residual.data(), static_cast<Eigen::Index>(n));
  std::vector<double> out(n);
  for (std::size_t b = 0; b < kBlocks; ++b) {
    std::vector<Eigen::Index> train;
    double from_s = 1e300, to_s = -1e300;  // the held-out block's time span [s]
    for (std::size_t k = 0; k < n; ++k) {
      const bool held_out = block_of(k, n) == b;
      if (!held_out) train.push_back(static_cast<Eigen::Index>(k));
      if (held_out)
        from_s = std::min(from_s, run.data->t_s[run.analysed[k]]),
        to_s = std::max(to_s, run.data->t_s[run.analysed[k]]);
    }
    Eigen::MatrixXd Xb;  // the columns as the other blocks can know them (steps_blinded)
    if (const auto blinded = steps_blinded(run, from_s, to_s)) {
      std::vector<double> unused;
      predictor.evaluate(*blinded, params, run.analysed, unused, &Xb, nullptr, eye);
    }
    const Eigen::MatrixXd& X = Xb.size() > 0 ? Xb : Xall;
    const Eigen::MatrixXd Xt = X(train, Eigen::all);
    const Eigen::VectorXd rt = r(train);
    const Eigen::VectorXd beta = solve_linear(Xt, rt);
    for (std::size_t k = 0; k < n; ++k) {
      if (block_of(k, n) == b) out[k] = residual[k] - X.row(static_cast<Eigen::Index>(k)).dot(beta);
    }
  }
  return out;
}

CvResult cross_validate(const std::vector<const PreparedRun*>& runs,
                        const TrainedModelFor& model_for, int max_folds) {
  if (runs.size() == 1) return within_run(*runs.front(), model_for);
  CvResult out;
  const TrainedModel full = model_for(runs);
  out.full = Fitter(*full.predictor, runs).fit(full.start);
  out.full_forms = full.forms;
  const std::size_t folds = std::min<std::size_t>(static_cast<std::size_t>(max_folds), runs.size());
  std::vector<std::vector<double>> residuals(runs.size());
  std::vector<double> own_sse(runs.size()), own_rho(runs.size());
  for (std::size_t f = 0; f < folds; ++f) {
    std::vector<const PreparedRun*> train;
    for (std::size_t r = 0; r < runs.size(); ++r) {
      if (r % folds != f) train.push_back(runs[r]);
    }
    // Chosen on the training runs alone: the held-out runs reach no choice of their fold.
    const TrainedModel fold = model_for(train);
    out.folds.push_back(Fitter(*fold.predictor, train).fit(fold.start));
    out.fold_forms.push_back(fold.forms);
    const FitResult& fit = out.folds.back();
    for (std::size_t r = f; r < runs.size(); r += folds) {
      residuals[r] = held_out_residuals(*fold.predictor, *runs[r], fit.params);
      const std::vector<double> own = own_eye_residuals(*fold.predictor, *runs[r], fit.params);
      own_sse[r] = sum_of_squares(own);
      own_rho[r] = lag1(own);
    }
  }
  for (auto& residual : residuals) add_run(out, std::move(residual));
  out.own_eye_run_sse = std::move(own_sse);
  out.own_eye_run_rho = std::move(own_rho);
  finish(out);
  return out;
}

}  // namespace rig::model
