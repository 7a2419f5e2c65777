#include "puncture_law.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "eye_variation.hpp"
#include "fitter.hpp"

namespace rig::model {
namespace {

constexpr int kTauIterations = 30;
constexpr double kTauTolerance = 1e-6;  // relative change of tau^2 + mean v that ends the iteration
constexpr double kBoundMargin =
    0.01;  // placed values stay this share of their range inside a bound

// One shared parameter of a term that is a coefficient of the puncture depth.
struct LawSlot {
  std::size_t term = 0;
  std::size_t param = 0;
  double lower = 0.0, upper = 0.0;
};

std::vector<LawSlot> law_slots(const Predictor& predictor, const PreparedRun& run) {
  std::vector<LawSlot> out;
  std::vector<double> values;
  for (std::size_t k = 0; k < predictor.terms().size(); ++k) {
    const auto specs = predictor.terms()[k]->shared_params();
    for (const std::size_t j : predictor.terms()[k]->puncture_regressors(run, values)) {
      if (j < specs.size()) out.push_back({k, j, specs[j].lower, specs[j].upper});
    }
  }
  return out;
}

// The regressors of every run, one row each: 1 (with `level`), then each slot's value.
Eigen::MatrixXd law_design(const Predictor& predictor, const std::vector<const PreparedRun*>& runs,
                           bool level) {
  const std::size_t slots = law_slots(predictor, *runs.front()).size();
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(runs.size()),
                                            static_cast<Eigen::Index>(slots + (level ? 1 : 0)));
  std::vector<double> values;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    Eigen::Index c = 0;
    if (level) X(static_cast<Eigen::Index>(r), c++) = 1.0;
    for (const EffectTerm* term : predictor.terms()) {
      term->puncture_regressors(*runs[r], values);
      for (const double v : values) {
        if (c < X.cols()) X(static_cast<Eigen::Index>(r), c++) = v;
      }
    }
  }
  return X;
}

double held_inside(double value, double lower, double upper) {
  const double margin = kBoundMargin * (upper - lower);
  return std::clamp(value, lower + margin, upper - margin);
}

double bounded_param(const char* name, bool upper) {
  for (const BaselineParam& b : baseline_parameters()) {
    if (std::string(name) == b.name) return upper ? b.upper : b.lower;
  }
  return 0.0;
}

// Adds the regression's coefficients (changes: the shifts were measured under the law so far).
void add_changes(const std::vector<LawSlot>& slots, const Eigen::VectorXd& change, bool level,
                 ModelParams& p) {
  Eigen::Index c = 0;
  if (level) {
    p.base.x_pi_shift =
        held_inside(p.base.x_pi_shift + change(c++), bounded_param("x_pi_shift", false),
                    bounded_param("x_pi_shift", true));
  }
  for (const LawSlot& s : slots) {
    double& value = p.shared[s.term][s.param];
    value = held_inside(value + change(c++), s.lower, s.upper);
  }
}

}  // namespace

ShiftRegression regress_shifts(const std::vector<double>& shifts_mm,
                               const std::vector<double>& variances_mm2, const Eigen::MatrixXd& X) {
  ShiftRegression out;
  out.coefficients = Eigen::VectorXd::Zero(X.cols());
  std::vector<Eigen::Index> rows;
  for (std::size_t r = 0; r < shifts_mm.size() && r < variances_mm2.size(); ++r) {
    if (std::isfinite(variances_mm2[r]) && variances_mm2[r] > 0.0 && std::isfinite(shifts_mm[r]))
      rows.push_back(static_cast<Eigen::Index>(r));
  }
  out.runs = static_cast<int>(rows.size());
  if (out.runs <= X.cols()) return out;
  const Eigen::MatrixXd A = X(rows, Eigen::all);
  Eigen::VectorXd d(out.runs), v(out.runs);
  for (int n = 0; n < out.runs; ++n)
    d(n) = shifts_mm[static_cast<std::size_t>(rows[n])],
    v(n) = variances_mm2[static_cast<std::size_t>(rows[n])];
  const std::vector<double> variances(v.data(), v.data() + v.size());
  double tau2 = 0.0;
  for (int it = 0; it < kTauIterations; ++it) {
    const Eigen::VectorXd w =
        (tau2 + v.array()).inverse().sqrt().matrix();  // sqrt of the GLS weights [1/mm]
    out.coefficients = (w.asDiagonal() * A).colPivHouseholderQr().solve(w.cwiseProduct(d));
    const Eigen::VectorXd e = d - A * out.coefficients;
    const double next = eye_parameter_variance(std::vector<double>(e.data(), e.data() + e.size()),
                                               variances, static_cast<int>(A.cols()));
    const bool settled = std::abs(next - tau2) <= kTauTolerance * (next + v.mean());
    tau2 = next;
    if (settled) break;
  }
  out.tau2_mm2 = tau2;
  out.solved = out.coefficients.allFinite();
  return out;
}

bool has_puncture_law(const Predictor& predictor, const std::vector<const PreparedRun*>& runs) {
  return !runs.empty() && !law_slots(predictor, *runs.front()).empty();
}

PlacedLaw place_puncture_law(const Predictor& predictor,
                             const std::vector<const PreparedRun*>& runs, ModelParams& p,
                             const std::vector<Eigen::VectorXd>& betas, bool level) {
  PlacedLaw out;
  if (!has_puncture_law(predictor, runs)) return out;
  const std::vector<LawSlot> slots = law_slots(predictor, *runs.front());
  const Eigen::MatrixXd X = law_design(predictor, runs, level);
  for (int round = 0; round < kLawMaxRounds; ++round) {
    std::vector<double> shifts, variances;
    for (const OwnShift& s : own_puncture_shifts(predictor, runs, p, betas))
      shifts.push_back(s.shift_mm), variances.push_back(s.variance_mm2);
    const ShiftRegression fit = regress_shifts(shifts, variances, X);
    if (!fit.solved) break;
    const ModelParams before = p;
    add_changes(slots, fit.coefficients, level, p);
    // How far each run's depth moved this round, as held inside the bounds [mm].
    Eigen::VectorXd now = Eigen::VectorXd::Zero(X.cols()), was = Eigen::VectorXd::Zero(X.cols());
    Eigen::Index c = 0;
    if (level) now(c) = p.base.x_pi_shift, was(c) = before.base.x_pi_shift, ++c;
    for (const LawSlot& s : slots)
      now(c) = p.shared[s.term][s.param], was(c) = before.shared[s.term][s.param], ++c;
    out.placed = true;
    out.rounds = round + 1;
    out.last_move_mm = (X * (now - was)).cwiseAbs().maxCoeff();
    out.tau_mm = std::sqrt(fit.tau2_mm2);
    if (out.last_move_mm <= kLawTolerance_mm) break;
  }
  return out;
}

}  // namespace rig::model
