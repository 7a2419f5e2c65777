#include "fitter.hpp"

#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>

#include <cmath>

#include "puncture_law.hpp"

namespace rig::model {

const std::vector<BaselineParam>& baseline_parameters() {
  static const std::vector<BaselineParam> kParams = {
      {"a", "N/mm", &ContinuousParams::a, 0.0, 0.2},
      {"b", "N/mm", &ContinuousParams::b, 0.0, 1.0},
      {"d", "N", &ContinuousParams::d, -0.2, 0.2},
      {"f", "1/mm", &ContinuousParams::f, -3.0, 3.0},
      {"g", "N/mmHg", &ContinuousParams::g, -0.1, 0.1},
      {"g0", "N", &ContinuousParams::g0, -2.0, 2.0},
      {"x_c", "mm", &ContinuousParams::x_c, 1.0, 14.0},
      {"w_drop", "mm", &ContinuousParams::w_drop, 0.005, 1.0},
      {"w_release", "mm", &ContinuousParams::w_release, 0.002, 1.0},
      {"x_pi_shift", "mm", &ContinuousParams::x_pi_shift, -2.0, 2.0},
      {"x_pf_shift", "mm", &ContinuousParams::x_pf_shift, -3.0, 5.0},
  };
  return kParams;
}

namespace {

double to_bounded(double u, double lo, double hi) {
  return lo + (hi - lo) * (1.0 + std::sin(u)) * 0.5;
}
double from_bounded(double x, double lo, double hi) {
  const double s = std::clamp(2.0 * (x - lo) / (hi - lo) - 1.0, -1.0 + 1e-9, 1.0 - 1e-9);
  return std::asin(s);
}

}  // namespace

Fitter::Fitter(const Predictor& predictor, std::vector<const PreparedRun*> runs, bool fit_baseline,
               bool eyes_differ)
    : predictor_(&predictor),
      runs_(std::move(runs)),
      fit_baseline_(fit_baseline),
      eyes_differ_(eyes_differ) {
  if (fit_baseline_) {
    for (const auto& b : baseline_parameters()) specs_.push_back({b.lower, b.upper, true});
  }
  for (const EffectTerm* t : predictor.terms()) {
    for (const ParamSpec& s : t->shared_params())
      specs_.push_back({s.lower, s.upper, s.lower < s.upper});
  }
  for (const PreparedRun* r : runs_) rows_ += r->fit_rows.size();
}

Eigen::VectorXd Fitter::pack(const ModelParams& p) const {
  Eigen::VectorXd u(static_cast<Eigen::Index>(specs_.size()));
  Eigen::Index k = 0;
  auto put = [&](double value) {
    const Spec& s = specs_[static_cast<std::size_t>(k)];
    u(k++) = s.bounded ? from_bounded(value, s.lower, s.upper) : value;
  };
  if (fit_baseline_) {
    for (const auto& b : baseline_parameters()) put(p.base.*(b.member));
  }
  for (const auto& values : p.shared) {
    for (const double v : values) put(v);
  }
  return u;
}

ModelParams Fitter::unpack(const Eigen::VectorXd& u, const ModelParams& start) const {
  ModelParams p = start;
  Eigen::Index k = 0;
  auto take = [&]() {
    const Spec& s = specs_[static_cast<std::size_t>(k)];
    const double v = u(k++);
    return s.bounded ? to_bounded(v, s.lower, s.upper) : v;
  };
  if (fit_baseline_) {
    for (const auto& b : baseline_parameters()) p.base.*(b.member) = take();
  }
  for (auto& values : p.shared) {
    for (double& v : values) v = take();
  }
  return p;
}

std::vector<double> Fitter::residuals(const Predictor& predictor, const PreparedRun& run,
                                      const ModelParams& p, const std::vector<std::size_t>& rows,
                                      Eigen::VectorXd* coefficients, const EyeParams* eye) {
  std::vector<double> prediction;
  Eigen::MatrixXd X;
  predictor.evaluate(run, p, rows, prediction, predictor.linear_columns() > 0 ? &X : nullptr,
                     nullptr, eye);
  std::vector<double> r(rows.size());
  const bool packed = &rows == &run.fit_rows && run.fit_inputs.size() == rows.size();
  for (std::size_t n = 0; n < rows.size(); ++n)
    r[n] = (packed ? run.fit_inputs[n] : run.inputs[rows[n]]).force_N - prediction[n];
  if (predictor.linear_columns() > 0) {
    const Eigen::Map<Eigen::VectorXd> rv(r.data(), static_cast<Eigen::Index>(r.size()));
    const Eigen::VectorXd beta = solve_linear(X, rv);
    const Eigen::VectorXd rest = rv - X * beta;
    for (std::size_t n = 0; n < r.size(); ++n) r[n] = rest(static_cast<Eigen::Index>(n));
    if (coefficients != nullptr) *coefficients = beta;
  }
  return r;
}

void Fitter::evaluate_all(const ModelParams& p, const std::vector<EyeParams>& eyes,
                          Eigen::VectorXd* fvec, Eigen::VectorXd& gamma,
                          std::vector<Eigen::VectorXd>& betas) const {
  betas.assign(runs_.size(), Eigen::VectorXd());
  if (predictor_->shared_columns() == 0) {
    Eigen::Index k = 0;
    for (std::size_t r = 0; r < runs_.size(); ++r) {
      for (const double e :
           residuals(*predictor_, *runs_[r], p, runs_[r]->fit_rows, &betas[r], &eyes[r])) {
        if (fvec != nullptr) (*fvec)(k) = e;
        ++k;
      }
    }
    gamma = Eigen::VectorXd();
    return;
  }
  std::vector<Eigen::VectorXd> r(runs_.size());
  std::vector<Eigen::MatrixXd> X(runs_.size()), S(runs_.size());
  Eigen::Index rows = 0;
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    std::vector<double> prediction;
    const auto& fit_rows = runs_[i]->fit_rows;
    predictor_->evaluate(*runs_[i], p, fit_rows, prediction,
                         predictor_->linear_columns() > 0 ? &X[i] : nullptr, &S[i], &eyes[i]);
    r[i].resize(static_cast<Eigen::Index>(fit_rows.size()));
    const bool packed = runs_[i]->fit_inputs.size() == fit_rows.size();
    for (std::size_t n = 0; n < fit_rows.size(); ++n) {
      const SampleInputs& in = packed ? runs_[i]->fit_inputs[n] : runs_[i]->inputs[fit_rows[n]];
      r[i](static_cast<Eigen::Index>(n)) = in.force_N - prediction[n];
    }
    rows += r[i].size();
  }
  const Eigen::Index shared = predictor_->shared_columns();
  gamma = Eigen::VectorXd::Zero(shared);
  for (int pass = 0; pass < 3; ++pass) {  // alternate: per-run given shared, shared given per-run
    Eigen::MatrixXd stacked(rows, shared);
    Eigen::VectorXd target(rows);
    Eigen::Index at = 0;
    for (std::size_t i = 0; i < runs_.size(); ++i) {
      const Eigen::VectorXd rest = r[i] - S[i] * gamma;
      betas[i] = X[i].cols() > 0 ? solve_linear(X[i], rest) : Eigen::VectorXd();
      stacked.middleRows(at, r[i].size()) = S[i];
      target.segment(at, r[i].size()) =
          betas[i].size() > 0 ? Eigen::VectorXd(r[i] - X[i] * betas[i]) : r[i];
      at += r[i].size();
    }
    gamma = solve_linear(stacked, target);
  }
  Eigen::Index k = 0;
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    Eigen::VectorXd e = r[i] - S[i] * gamma;
    if (betas[i].size() > 0) e -= X[i] * betas[i];
    if (fvec != nullptr) fvec->segment(k, e.size()) = e;
    k += e.size();
  }
}

double Fitter::sse(const ModelParams& p) const {
  Eigen::VectorXd fvec = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(rows_));
  Eigen::VectorXd gamma;
  std::vector<Eigen::VectorXd> betas;
  evaluate_all(p, std::vector<EyeParams>(runs_.size()), &fvec, gamma, betas);
  return fvec.squaredNorm();
}

// Weight of the pull toward the start values [N per unit of the transformed parameter]:
// like one extra row with a 1 mN error per unit of change, nothing against hundreds of rows
// wherever the data constrain a parameter.
constexpr double kStartPull_N = 1e-3;

struct FitFunctor {
  using Scalar = double;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;

  const Fitter* fitter;
  const ModelParams* start;
  const std::vector<EyeParams>* eyes;
  int inputs() const { return static_cast<int>(fitter->specs_.size()); }
  const Eigen::VectorXd* start_u;
  int values() const { return static_cast<int>(fitter->rows_ + fitter->specs_.size()); }
  int operator()(const Eigen::VectorXd& u, Eigen::VectorXd& fvec) const {
    fvec.setZero(values());
    Eigen::VectorXd gamma;
    std::vector<Eigen::VectorXd> betas;
    fitter->evaluate_all(fitter->unpack(u, *start), *eyes, &fvec, gamma, betas);
    // A weak pull toward the start values: it only decides directions the data leave flat
    // (g against g0 when the training runs share one IOP), which would otherwise wander.
    fvec.tail(static_cast<Eigen::Index>(fitter->specs_.size())) = kStartPull_N * (u - *start_u);
    return 0;
  }
};

FitResult Fitter::minimise(const ModelParams& start, const std::vector<EyeParams>& eyes,
                           int max_evaluations) const {
  FitResult result;
  result.params = start;
  result.converged = true;  // nothing to fit is not a failure
  if (!specs_.empty() && rows_ > specs_.size()) {
    const Eigen::VectorXd u0 = pack(start);
    FitFunctor functor{this, &start, &eyes, &u0};
    Eigen::NumericalDiff<FitFunctor> numeric(functor);
    Eigen::LevenbergMarquardt<Eigen::NumericalDiff<FitFunctor>> lm(numeric);
    lm.parameters.maxfev = max_evaluations;
    lm.parameters.xtol = 1e-8;
    lm.parameters.ftol = 1e-10;
    Eigen::VectorXd u = u0;
    const auto status = lm.minimize(u);
    result.params = unpack(u, start);
    result.evaluations = static_cast<int>(lm.nfev);
    result.left_start = (u - u0).cwiseAbs().maxCoeff() > 0.0;
    result.converged =
        status == Eigen::LevenbergMarquardtSpace::RelativeErrorTooSmall ||
        status == Eigen::LevenbergMarquardtSpace::RelativeReductionTooSmall ||
        status == Eigen::LevenbergMarquardtSpace::RelativeErrorAndReductionTooSmall ||
        status == Eigen::LevenbergMarquardtSpace::XtolTooSmall;
  }
  result.eyes = eyes;
  Eigen::VectorXd fvec = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(rows_));
  evaluate_all(result.params, eyes, &fvec, result.params.shared_linear, result.run_coefficients);
  result.rmse_N = rows_ > 0 ? std::sqrt(fvec.squaredNorm() / static_cast<double>(rows_)) : 0.0;
  return result;
}

EyeDof Fitter::eye_level_params(const ModelParams& p) const {
  // The baseline's fitted stiffnesses and puncture shift set each eye parameter's level.
  EyeDof dof = fit_baseline_ ? EyeDof{1, 1, 1} : EyeDof{};
  const auto& terms = predictor_->terms();
  for (std::size_t k = 0; k < terms.size() && k < p.shared.size(); ++k)
    dof += terms[k]->eye_level_params(p.shared[k].data());
  return dof;
}

// A law of the puncture depth (puncture_law.hpp) is placed from the eyes' own shifts before
// the first fit and again on its result, then refitted: between fit rows the error is flat in
// the law's slopes, and the fit alone leaves them where they start.
FitResult Fitter::population_fit(const ModelParams& start, int max_evaluations) const {
  const std::vector<EyeParams> none(runs_.size());
  if (runs_.size() < kMinLawRuns || !has_puncture_law(*predictor_, runs_))
    return minimise(start, none, max_evaluations);
  ModelParams placed = start;
  place_puncture_law(*predictor_, runs_, placed, {}, fit_baseline_);
  const FitResult first = minimise(placed, none, max_evaluations);
  ModelParams again = first.params;
  place_puncture_law(*predictor_, runs_, again, first.run_coefficients, fit_baseline_);
  FitResult second = minimise(again, none, max_evaluations / 2);
  second.evaluations += first.evaluations;
  second.left_start = true;  // the law was placed away from its start
  return second.rmse_N <= first.rmse_N ? second : first;
}

FitResult Fitter::fit(const ModelParams& start, int max_evaluations) const {
  FitResult result = population_fit(start, max_evaluations);
  if (!eyes_differ_) return result;
  // Alternate: eyes given the shared parameters, shared parameters given the eyes. Eye-free
  // data give no spread and stop after the first estimate.
  for (int round = 0; round < 2; ++round) {
    const EyeEstimate eyes =
        estimate_eyes(*predictor_, runs_, result.params, result.run_coefficients,
                      eye_level_params(result.params));
    if (!eyes.spread.any()) break;
    const int evaluations = result.evaluations;
    const bool left_start = result.left_start;
    result = minimise(result.params, eyes.eyes, max_evaluations / 2);
    result.eye_spread = eyes.spread;
    result.evaluations += evaluations;
    result.left_start = result.left_start || left_start;
  }
  result.start_shared = start.shared;
  return result;
}

}  // namespace rig::model
