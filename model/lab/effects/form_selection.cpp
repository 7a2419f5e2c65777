#include "form_selection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "effect_util.hpp"
#include "family_term.hpp"
#include "fitter.hpp"
#include "puncture_law.hpp"

namespace rig::model::effects {
namespace {

constexpr std::size_t kMaxRuns = 8;
constexpr std::size_t kMaxRows = 300;
constexpr int kMaxEvaluations = 200;

// At most kMaxRuns runs, evenly spread, each with its fit rows thinned to kMaxRows.
std::vector<PreparedRun> selection_runs(const std::vector<const PreparedRun*>& runs) {
  std::vector<PreparedRun> out;
  const std::size_t take = std::min(runs.size(), kMaxRuns);
  for (std::size_t k = 0; k < take; ++k) {
    PreparedRun run = *runs[k * runs.size() / take];
    if (run.fit_rows.size() > kMaxRows) {
      std::vector<std::size_t> thinned;
      for (std::size_t j = 0; j < kMaxRows; ++j)
        thinned.push_back(run.fit_rows[j * run.fit_rows.size() / kMaxRows]);
      run.fit_rows = std::move(thinned);
    }
    out.push_back(std::move(run));
  }
  return out;
}

// Sum of squares and effective sample count of the residuals at the fit rows.
std::pair<double, double> sse_and_n_effective(const Predictor& predictor,
                                              const std::vector<const PreparedRun*>& runs,
                                              const ModelParams& p) {
  double sse = 0.0, n_eff = 0.0;
  for (const PreparedRun* run : runs) {
    const std::vector<double> residual = Fitter::residuals(predictor, *run, p, run->fit_rows);
    const Eigen::Map<const Eigen::VectorXd> r(residual.data(),
                                              static_cast<Eigen::Index>(residual.size()));
    sse += r.squaredNorm();
    // Lag-1 autocorrelation, clamped like the diagnosis does (thinned rows are still correlated).
    const double rho =
        r.size() > 1 && r.squaredNorm() > 0.0
            ? std::clamp(r.head(r.size() - 1).dot(r.tail(r.size() - 1)) / r.squaredNorm(), 0.0,
                         0.99)
            : 0.0;
    n_eff += static_cast<double>(r.size()) * (1.0 - rho) / (1.0 + rho);
  }
  return {sse, std::max(n_eff, 2.0)};
}

// The best of the term's starting points (last in p.shared) by the fit-row error.
void pick_start(const Predictor& predictor, const std::vector<const PreparedRun*>& runs,
                const EffectTerm& term, ModelParams& p) {
  const auto starts = term.starts();
  if (starts.size() < 2) return;
  const bool fitted = term.fit_each_start();
  const Fitter scorer(predictor, runs, fitted);  // fitted starts move the baseline with them
  double best = std::numeric_limits<double>::infinity();
  for (const auto& candidate : starts) {
    ModelParams trial = p;
    trial.shared.back() = candidate;
    const double error =
        fitted ? scorer.fit(trial, kStartProbeEvaluations).rmse_N : scorer.sse(trial);
    if (error < best) best = error, p.shared.back() = candidate;
  }
}

// A form's start on the baseline's fit: Eq. 1's parameters, and the baseline's terms where
// they are these (a term in another form keeps its start).
ModelParams start_on_baseline(const Predictor& predictor, const SelectionBaseline& baseline) {
  ModelParams p = predictor.initial_params();
  p.base = baseline.fit.base;
  for (std::size_t k = 0; k < baseline.fit.shared.size() && k + 1 < p.shared.size(); ++k) {
    if (p.shared[k].size() == baseline.fit.shared[k].size()) p.shared[k] = baseline.fit.shared[k];
  }
  return p;
}

// A form's start on the model's own values: Eq. 1's from the model, the baseline's terms at
// their start values (as the baseline's own fit starts).
ModelParams start_on_model(const Predictor& predictor, const FormSelectionInput& in) {
  ModelParams p = predictor.initial_params();
  for (std::size_t k = 0; k < in.base_params.size() && k + 1 < p.shared.size(); ++k) {
    if (in.base_params[k].size() == p.shared[k].size()) p.shared[k] = in.base_params[k];
  }
  return p;
}

// The form fitted from `p` with the baseline (its best start first): the sum of squares at
// the fit rows [N^2]. The baseline is refitted with the form: held at its own fit, it favours
// the forms flexible enough to make up for what it absorbed of the effect.
double form_sse(const Predictor& predictor, const std::vector<const PreparedRun*>& runs,
                const EffectTerm& term, ModelParams p) {
  pick_start(predictor, runs, term, p);
  const FitResult fit = Fitter(predictor, runs).fit(p, kMaxEvaluations);
  return sse_and_n_effective(predictor, runs, fit.params).first;
}

std::string selection_note(const FormSelectionInput& in, const FormChoice& choice) {
  int next = -1;
  for (int f = 0; f < in.forms; ++f) {
    if (f != choice.form && std::isfinite(choice.bic[static_cast<std::size_t>(f)]) &&
        (next < 0 ||
         choice.bic[static_cast<std::size_t>(f)] < choice.bic[static_cast<std::size_t>(next)]))
      next = f;
  }
  std::string note = format("form chosen by BIC among %.0f", in.forms);
  if (next >= 0) {
    const auto term = in.make_form(next);
    note += " (next: " + term->form() +
            format(", BIC %+.0f)", choice.bic[static_cast<std::size_t>(next)] -
                                       choice.bic[static_cast<std::size_t>(choice.form)]);
  }
  return note;
}

}  // namespace

int form_parameter_count(const EffectTerm& term, const std::vector<const PreparedRun*>& runs) {
  int count = 0;
  for (const ParamSpec& s : term.shared_params()) count += s.unit == kFormLabelUnit ? 0 : 1;
  if (!term.per_run_coefficients()) return count + term.linear_columns();
  for (const PreparedRun* run : runs) count += term.run_parameters(*run);
  return count;
}

std::vector<const PreparedRun*> SelectionBaseline::run_pointers() const {
  std::vector<const PreparedRun*> out;
  for (const PreparedRun& r : runs) out.push_back(&r);
  return out;
}

SelectionBaseline fit_selection_baseline(const FormSelectionInput& in) {
  SelectionBaseline b;
  b.runs = selection_runs(in.runs);
  const auto runs = b.run_pointers();
  const Predictor base(*in.model, in.base_terms);
  b.fit = base.initial_params();
  for (std::size_t k = 0; k < in.base_params.size() && k < b.fit.shared.size(); ++k) {
    if (in.base_params[k].size() == b.fit.shared[k].size()) b.fit.shared[k] = in.base_params[k];
  }
  if (runs.empty()) return b;
  b.fit = Fitter(base, runs).fit(b.fit, 2 * kMaxEvaluations).params;
  b.n_effective = sse_and_n_effective(base, runs, b.fit).second;
  return b;
}

FormChoice select_form(const FormSelectionInput& in, const SelectionBaseline& baseline) {
  FormChoice choice;
  choice.bic.assign(static_cast<std::size_t>(in.forms), std::numeric_limits<double>::infinity());
  const auto runs = baseline.run_pointers();
  if (runs.empty() || in.forms < 2) return choice;
  std::size_t rows = 0;
  for (const PreparedRun* r : runs) rows += r->fit_rows.size();
  const double n_eff = baseline.n_effective;
  for (int f = 0; f < in.forms; ++f) {
    const auto term = in.make_form(f);
    std::vector<const EffectTerm*> terms = in.base_terms;
    terms.push_back(term.get());
    const Predictor predictor(*in.model, terms);
    double sse = form_sse(predictor, runs, *term, start_on_baseline(predictor, baseline));
    // A law of the puncture depth (puncture_law.hpp) is also fitted from the model's own
    // values, the law placed there: the baseline's puncture drop may have run to its bound,
    // where no fit moves it back, and the eyes' shifts then absorb what the law misses.
    if (has_puncture_law(predictor, runs))
      sse = std::min(sse, form_sse(predictor, runs, *term, start_on_model(predictor, in)));
    if (!std::isfinite(sse)) continue;
    const double mean_square =
        std::max(sse / static_cast<double>(std::max<std::size_t>(rows, 1)), 1e-300);
    choice.bic[static_cast<std::size_t>(f)] =
        n_eff * std::log(mean_square) + form_parameter_count(*term, runs) * std::log(n_eff);
  }
  choice.form =
      static_cast<int>(std::min_element(choice.bic.begin(), choice.bic.end()) - choice.bic.begin());
  choice.note = selection_note(in, choice);
  return choice;
}

}  // namespace rig::model::effects
