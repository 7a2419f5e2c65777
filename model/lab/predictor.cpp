#include "predictor.hpp"

#include <Eigen/Dense>
#include <algorithm>

#include "model_lint.hpp"

namespace rig::model {
namespace {
// How many rows ahead a row's inputs are fetched: a row costs ~0.1-0.3 us of arithmetic, a
// cache miss ~0.1 us, so a few rows ahead hide it.
constexpr std::size_t kPrefetchRows = 8;

// Row sets other than the fit rows (scoring, eyes) are ~20 samples apart: a cache miss each
// unless asked for ahead.
void prefetch_ahead(const PreparedRun& run, const std::vector<std::size_t>& rows, std::size_t n) {
  if (n + kPrefetchRows >= rows.size()) return;
  const char* ahead = reinterpret_cast<const char*>(&run.inputs[rows[n + kPrefetchRows]]);
  __builtin_prefetch(ahead);
  __builtin_prefetch(ahead + sizeof(SampleInputs) - 1);  // a record can span two cache lines
}
}  // namespace

Predictor::Predictor(const ForceModel& model, std::vector<const EffectTerm*> terms)
    : model_(model), terms_(std::move(terms)) {
  // Never run a printed-form file silently as our continuous reading (its parameters would
  // be the interpreted defaults, not the file's): the lab fits the continuous form only.
  if (model_.form != ModelForm::kContinuous)
    throw ModelFileError(printed_form_refusal(model_, "the model lab"));
  for (const EffectTerm* t : terms_)
    (t->per_run_coefficients() ? linear_columns_ : shared_columns_) += t->linear_columns();
}

ModelParams Predictor::initial_params() const {
  ModelParams p;
  p.base = model_.params;
  for (const EffectTerm* t : terms_) {
    std::vector<double> values;
    for (const ParamSpec& s : t->shared_params()) values.push_back(s.initial);
    p.shared.push_back(std::move(values));
  }
  p.shared_linear = Eigen::VectorXd::Zero(shared_columns_);
  return p;
}

void Predictor::evaluate(const PreparedRun& run, const ModelParams& p,
                         const std::vector<std::size_t>& rows, std::vector<double>& out,
                         Eigen::MatrixXd* X, Eigen::MatrixXd* S, const EyeParams* eye,
                         EyeColumns* tissue) const {
  ForceModel m = model_;
  m.params = p.base;
  for (std::size_t k = 0; k < terms_.size(); ++k)
    terms_[k]->adjust_model(run, p.shared[k].data(), m.params);
  if (eye != nullptr) m.params.x_pi_shift += eye->x_pi_mm;
  out.resize(rows.size());
  if (tissue != nullptr)
    tissue->precut.assign(rows.size(), 0.0), tissue->cut.assign(rows.size(), 0.0);
  if (X != nullptr) X->resize(static_cast<Eigen::Index>(rows.size()), linear_columns_);
  if (S != nullptr) S->resize(static_cast<Eigen::Index>(rows.size()), shared_columns_);
  const ForceModel::RunDepths depths = m.depths(run.iop_mmHg);
  const double x_pi = depths.x_pi_mm;
  const double x_c = std::min(m.params.x_c, depths.x_pf_mm);
  std::vector<double> row(static_cast<std::size_t>(std::max(linear_columns_ + shared_columns_, 1)));
  // The run's fit rows (the fits' case, hundreds of times each): their inputs lie side by side.
  const bool packed = &rows == &run.fit_rows && run.fit_inputs.size() == rows.size();
  for (std::size_t n = 0; n < rows.size(); ++n) {
    const std::size_t i = rows[n];
    if (!packed) prefetch_ahead(run, rows, n);
    const SampleInputs& in = packed ? run.fit_inputs[n] : run.inputs[i];
    SampleView s{&run, i, in.x_mm, in.t_s, in.force_N, in.velocity_mm_s, in.hold_s, 0.0, in.phase};
    s.inputs = &in;
    s.x_pi_mm = x_pi;
    double shift = 0.0;        // of the tip now [mm]
    double front_shift = 0.0;  // of the tip's deepest point so far [mm]
    for (std::size_t k = 0; k < terms_.size(); ++k) {
      shift += terms_[k]->x_shift(s, p.shared[k].data());
      front_shift += terms_[k]->front_shift(s, p.shared[k].data());
    }
    const double tip_front_mm =
        in.front_mm - front_shift;  // where the blade has been (Eq. 1's phases)
    s.inserted_mm = std::max(0.0, std::min(s.x_mm - shift, tip_front_mm) - x_pi);
    s.after_puncture = tip_front_mm >= x_pi;
    s.cutting = s.after_puncture && s.x_mm - shift < x_c &&
                (s.phase != Phase::kHold && s.phase != Phase::kRetraction);
    double scale = 1.0;
    for (std::size_t k = 0; k < terms_.size(); ++k)
      scale *= terms_[k]->scale(s, p.shared[k].data());
    double force = m.baseline(s.x_mm - shift, tip_front_mm, depths) * scale;
    if (tissue != nullptr) (s.after_puncture ? tissue->cut : tissue->precut)[n] = force;
    if (eye != nullptr) force *= 1.0 + (s.after_puncture ? eye->cut_scale : eye->precut_scale);
    double added = 0.0;
    for (std::size_t k = 0; k < terms_.size(); ++k)
      added += terms_[k]->add(s, p.shared[k].data(), force);
    out[n] = force + added;
    if ((X != nullptr && linear_columns_ > 0) || (S != nullptr && shared_columns_ > 0))
      write_design(s, p, n, X, S, row.data());
  }
  if (S == nullptr && shared_columns_ > 0 && p.shared_linear.size() == shared_columns_) {
    // No caller wants the shared columns: apply the known shared coefficients directly.
    Eigen::MatrixXd shared_design;
    std::vector<double> ignored;
    evaluate(run, p, rows, ignored, nullptr, &shared_design, eye);
    const Eigen::VectorXd add = shared_design * p.shared_linear;
    for (std::size_t n = 0; n < rows.size(); ++n) out[n] += add(static_cast<Eigen::Index>(n));
  }
}

// Row n of the design matrices: per-run columns into X, shared ones into S (either may be null).
void Predictor::write_design(const SampleView& s, const ModelParams& p, std::size_t n,
                             Eigen::MatrixXd* X, Eigen::MatrixXd* S, double* row) const {
  int column = 0;
  int shared_column = 0;
  for (std::size_t k = 0; k < terms_.size(); ++k) {
    const int columns = terms_[k]->linear_columns();
    if (columns == 0) continue;
    terms_[k]->design(s, p.shared[k].data(), row);
    const bool own = terms_[k]->per_run_coefficients();
    Eigen::MatrixXd* target = own ? X : S;
    int& at = own ? column : shared_column;
    if (target != nullptr) {
      for (int c = 0; c < columns; ++c) (*target)(static_cast<Eigen::Index>(n), at + c) = row[c];
    }
    at += columns;
  }
}

Eigen::VectorXd solve_linear(const Eigen::MatrixXd& X, const Eigen::VectorXd& residual) {
  if (X.cols() == 0 || X.rows() == 0) return Eigen::VectorXd();
  // Ridge-regularised normal equations on column-scaled X: well conditioned and cheap.
  Eigen::VectorXd scale = X.colwise().norm().transpose();
  for (Eigen::Index c = 0; c < scale.size(); ++c) scale(c) = scale(c) > 1e-12 ? scale(c) : 1.0;
  const Eigen::MatrixXd Xs = X * scale.cwiseInverse().asDiagonal();
  Eigen::MatrixXd A = Xs.transpose() * Xs;
  A.diagonal().array() += 1e-6;
  const Eigen::VectorXd beta = A.ldlt().solve(Xs.transpose() * residual);
  return beta.cwiseQuotient(scale);
}

}  // namespace rig::model
