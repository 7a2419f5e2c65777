#include "eye_variation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rig::model {
namespace {

constexpr std::size_t kMinRuns = 3;     // fewer: no population to shrink toward
constexpr double kShiftRange_mm = 0.6;  // puncture shifts searched: +-0.6 mm
constexpr double kShiftStep_mm = 0.05;  // grid step, then golden refinement
constexpr double kWindow_mm = 0.8;      // rows this close to the model's puncture carry the shift
constexpr double kUnknown = std::numeric_limits<double>::infinity();

// One run's residuals (measured - prediction - instrument columns) at `rows` for an eye.
struct RunResidual {
  const Predictor* predictor;
  const PreparedRun* run;
  const ModelParams* p;
  const Eigen::VectorXd* beta;

  std::vector<double> at(const std::vector<std::size_t>& rows, const EyeParams& eye,
                         EyeColumns* tissue = nullptr) const {
    std::vector<double> prediction;
    Eigen::MatrixXd X;
    const bool linear =
        predictor->linear_columns() > 0 && beta->size() == predictor->linear_columns();
    predictor->evaluate(*run, *p, rows, prediction, linear ? &X : nullptr, nullptr, &eye, tissue);
    std::vector<double> r(rows.size());
    for (std::size_t n = 0; n < rows.size(); ++n) {
      r[n] = run->inputs[rows[n]].force_N - prediction[n];
      if (linear) r[n] -= X.row(static_cast<Eigen::Index>(n)).dot(*beta);
    }
    return r;
  }
  double sse(const std::vector<std::size_t>& rows, const EyeParams& eye) const {
    double sum = 0.0;
    for (const double e : at(rows, eye)) sum += e * e;
    return sum;
  }
};

struct RunEstimate {
  EyeParams eye;
  double var_precut = kUnknown;  // sampling variances of the unpenalised estimates
  double var_cut = kUnknown;
  double var_shift = kUnknown;
};

std::vector<std::size_t> rows_near_puncture(const Predictor& predictor, const PreparedRun& run,
                                            const ModelParams& p) {
  ForceModel m = predictor.model();
  m.params = p.base;
  for (std::size_t k = 0; k < predictor.terms().size(); ++k)
    predictor.terms()[k]->adjust_model(run, p.shared[k].data(), m.params);
  const double x_pi = m.puncture_depth_mm(run.iop_mmHg);
  std::vector<std::size_t> rows;
  for (const std::size_t i : run.fit_rows) {
    if (std::abs(run.data->x_mm[i] - x_pi) < kWindow_mm + kShiftRange_mm) rows.push_back(i);
  }
  // A run that never reaches the puncture says nothing about its depth.
  const bool reached = !run.front_mm.empty() && run.front_mm.back() > x_pi + kShiftRange_mm;
  return reached ? rows : std::vector<std::size_t>{};
}

// The puncture shift minimising the error near the puncture (scale held), and the error's
// curvature there for the sampling variance.
void fit_shift(const RunResidual& residual, const std::vector<std::size_t>& rows, double noise_N2,
               RunEstimate& e) {
  if (rows.size() < 5) return;
  auto sse = [&](double shift) {
    return residual.sse(rows, {e.eye.precut_scale, e.eye.cut_scale, shift});
  };
  double best = 0.0, best_sse = sse(0.0);
  for (double s = -kShiftRange_mm; s <= kShiftRange_mm + 1e-9; s += kShiftStep_mm) {
    const double value = sse(s);
    if (value < best_sse) best_sse = value, best = s;
  }
  double lo = best - kShiftStep_mm, hi = best + kShiftStep_mm;  // golden section refinement
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int it = 0; it < 10; ++it) {
    const double a = hi - g * (hi - lo), b = lo + g * (hi - lo);
    if (sse(a) < sse(b)) {
      hi = b;
    } else {
      lo = a;
    }
  }
  e.eye.x_pi_mm = 0.5 * (lo + hi);
  const double h = 0.5 * kShiftStep_mm;
  const double curvature =
      (sse(e.eye.x_pi_mm + h) - 2.0 * sse(e.eye.x_pi_mm) + sse(e.eye.x_pi_mm - h)) / (h * h);
  e.var_shift = curvature > 0.0 ? 2.0 * noise_N2 / curvature : kUnknown;
}

// The scales by least squares over all fit rows (the prediction is linear in them and each
// row carries one of the two).
void fit_scales(const RunResidual& residual, const PreparedRun& run, double& noise_N2,
                RunEstimate& e) {
  EyeColumns tissue;
  const std::vector<double> r = residual.at(run.fit_rows, {0.0, 0.0, e.eye.x_pi_mm}, &tissue);
  double pp = 0.0, pr = 0.0, cc = 0.0, cr = 0.0, rr = 0.0;
  for (std::size_t n = 0; n < r.size(); ++n) {
    pp += tissue.precut[n] * tissue.precut[n], pr += tissue.precut[n] * r[n];
    cc += tissue.cut[n] * tissue.cut[n], cr += tissue.cut[n] * r[n];
    rr += r[n] * r[n];
  }
  if (r.empty()) return;
  e.eye.precut_scale = pp > 0.0 ? pr / pp : 0.0;
  e.eye.cut_scale = cc > 0.0 ? cr / cc : 0.0;
  const double explained = (pp > 0.0 ? pr * pr / pp : 0.0) + (cc > 0.0 ? cr * cr / cc : 0.0);
  noise_N2 = std::max((rr - explained) / static_cast<double>(r.size()), 1e-12);
  e.var_precut = pp > 0.0 ? noise_N2 / pp : kUnknown;
  e.var_cut = cc > 0.0 ? noise_N2 / cc : kUnknown;
}

RunEstimate estimate_run(const Predictor& predictor, const PreparedRun& run, const ModelParams& p,
                         const Eigen::VectorXd& beta) {
  const RunResidual residual{&predictor, &run, &p, &beta};
  const std::vector<std::size_t> near = rows_near_puncture(predictor, run, p);
  RunEstimate e;
  double noise_N2 = 0.0;
  fit_scales(residual, run, noise_N2, e);
  for (int round = 0; round < 2; ++round) {  // alternate: shift given scales, scales given shift
    fit_shift(residual, near, noise_N2, e);
    fit_scales(residual, run, noise_N2, e);
  }
  return e;
}

// The spread (tau) of one eye parameter over the runs with a finite sampling variance.
double spread_of(const std::vector<RunEstimate>& estimates, double EyeParams::*member,
                 double RunEstimate::*variance, int fitted) {
  std::vector<double> deviations, variances;
  for (const RunEstimate& e : estimates) {
    if (!std::isfinite(e.*variance)) continue;
    deviations.push_back(e.eye.*member);
    variances.push_back(e.*variance);
  }
  if (deviations.size() < kMinRuns) return 0.0;
  return std::sqrt(eye_parameter_variance(deviations, variances, fitted));
}

double shrink(double value, double variance, double tau) {
  if (tau <= 0.0 || !std::isfinite(variance)) return 0.0;
  return value * tau * tau / (tau * tau + variance);
}

}  // namespace

// The d_r are what the population model leaves of each eye after `fitted` parameters were
// fitted on one value per eye: they took that many degrees of freedom, as a sample
// variance's mean takes one. Over 9 eyes, a covariate's two slopes on the cutting scale
// would otherwise leave tau^2 at 6/9 of the truth (draw 200038: a floor of 5.5 mN against a
// true 7.6 before 2026-11-29).
double eye_parameter_variance(const std::vector<double>& deviations,
                              const std::vector<double>& variances, int fitted) {
  if (deviations.empty()) return 0.0;
  double squares = 0.0, mean_variance = 0.0;
  for (const double d : deviations) squares += d * d;
  for (const double v : variances) mean_variance += v / static_cast<double>(variances.size());
  const double left = std::max(
      1.0, static_cast<double>(deviations.size()) - static_cast<double>(std::max(fitted, 0)));
  return std::max(0.0, squares / left - mean_variance);
}

EyeEstimate estimate_eyes(const Predictor& predictor, const std::vector<const PreparedRun*>& runs,
                          const ModelParams& p, const std::vector<Eigen::VectorXd>& betas,
                          const EyeDof& fitted) {
  EyeEstimate out;
  out.eyes.assign(runs.size(), EyeParams{});
  if (runs.size() < kMinRuns) return out;
  std::vector<RunEstimate> estimates;
  const Eigen::VectorXd none;
  for (std::size_t r = 0; r < runs.size(); ++r)
    estimates.push_back(estimate_run(predictor, *runs[r], p, r < betas.size() ? betas[r] : none));
  out.spread.precut_scale =
      spread_of(estimates, &EyeParams::precut_scale, &RunEstimate::var_precut, fitted.precut_scale);
  out.spread.cut_scale =
      spread_of(estimates, &EyeParams::cut_scale, &RunEstimate::var_cut, fitted.cut_scale);
  out.spread.x_pi_mm =
      spread_of(estimates, &EyeParams::x_pi_mm, &RunEstimate::var_shift, fitted.x_pi_mm);
  for (std::size_t r = 0; r < runs.size(); ++r) {
    out.eyes[r].precut_scale =
        shrink(estimates[r].eye.precut_scale, estimates[r].var_precut, out.spread.precut_scale);
    out.eyes[r].cut_scale =
        shrink(estimates[r].eye.cut_scale, estimates[r].var_cut, out.spread.cut_scale);
    out.eyes[r].x_pi_mm =
        shrink(estimates[r].eye.x_pi_mm, estimates[r].var_shift, out.spread.x_pi_mm);
  }
  return out;
}

EyeParams own_eye(const Predictor& predictor, const PreparedRun& run, const ModelParams& p,
                  const Eigen::VectorXd& beta) {
  return estimate_run(predictor, run, p, beta).eye;
}

std::vector<OwnShift> own_puncture_shifts(const Predictor& predictor,
                                          const std::vector<const PreparedRun*>& runs,
                                          const ModelParams& p,
                                          const std::vector<Eigen::VectorXd>& betas) {
  std::vector<OwnShift> out;
  const Eigen::VectorXd none;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const RunEstimate e = estimate_run(predictor, *runs[r], p, r < betas.size() ? betas[r] : none);
    out.push_back({e.eye.x_pi_mm, e.var_shift});
  }
  return out;
}

double eye_variance_N2(const Predictor& predictor, const std::vector<const PreparedRun*>& runs,
                       const ModelParams& p, const EyeSpread& spread) {
  if (!spread.any()) return 0.0;
  // 3-point Gauss-Hermite nodes and weights of a standard normal.
  const double nodes[3] = {-std::sqrt(3.0), 0.0, std::sqrt(3.0)};
  const double weights[3] = {1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0};
  double sum = 0.0, samples = 0.0;
  for (const PreparedRun* run : runs) {
    if (run->fit_rows.empty()) continue;
    std::vector<double> population, shifted;
    EyeColumns tissue;
    predictor.evaluate(*run, p, run->fit_rows, population);
    double expected = 0.0;
    for (int k = 0; k < 3; ++k) {
      const EyeParams eye{0.0, 0.0, nodes[k] * spread.x_pi_mm};
      predictor.evaluate(*run, p, run->fit_rows, shifted, nullptr, nullptr, &eye, &tissue);
      for (std::size_t n = 0; n < shifted.size(); ++n) {
        const double d = shifted[n] - population[n];
        const double pre = spread.precut_scale * tissue.precut[n],
                     cut = spread.cut_scale * tissue.cut[n];
        expected += weights[k] * (d * d + pre * pre + cut * cut);
      }
    }
    const double n_analysed = static_cast<double>(run->analysed.size());
    sum += expected / static_cast<double>(run->fit_rows.size()) * n_analysed;
    samples += n_analysed;
  }
  return samples > 0.0 ? sum / samples : 0.0;
}

}  // namespace rig::model
