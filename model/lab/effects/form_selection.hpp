#pragma once
// Picks the form of an effect family: fits the baseline once, then every form of the family
// together with the baseline (started from the baseline's fit), and keeps the form with
// the lowest BIC. The sample count is the autocorrelation-corrected
// effective one of the baseline's residuals (the same for every form), the parameter count
// the form's own: shared parameters + linear columns x runs (per-run columns) or x 1.
// For speed the fits use at most 8 runs, evenly spread, and 300 rows per run.
// A form with a law of the puncture depth (EffectTerm::puncture_regressors) is also fitted
// from the model's own values with the law placed (puncture_law.hpp), and keeps the better fit.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "effect_term.hpp"
#include "force_model.hpp"
#include "predictor.hpp"

namespace rig::model::effects {

struct FormChoice {
  int form = 0;
  std::string note;         // "form chosen by BIC among 4 (next: viscous, +31)"
  std::vector<double> bic;  // per form; +inf where the form could not be fitted
};

struct FormSelectionInput {
  const ForceModel* model = nullptr;
  std::vector<const EffectTerm*> base_terms;     // already in the model (saved, --with)
  std::vector<std::vector<double>> base_params;  // their start values, in order
  std::vector<const PreparedRun*> runs;
  int forms = 1;
  std::function<std::unique_ptr<EffectTerm>(int form)> make_form;
};

// The baseline every form is fitted over: the thinned runs and the baseline's own fit on
// them (shared by all families of a catalogue: fitted once).
struct SelectionBaseline {
  std::vector<PreparedRun> runs;
  ModelParams fit;
  double n_effective = 2.0;
  std::vector<const PreparedRun*> run_pointers() const;
};
SelectionBaseline fit_selection_baseline(const FormSelectionInput& in);

FormChoice select_form(const FormSelectionInput& in, const SelectionBaseline& baseline);

// Parameters a form costs in an information criterion (form labels excluded; per-run
// coefficients as each run uses them, EffectTerm::run_parameters).
int form_parameter_count(const EffectTerm& term, const std::vector<const PreparedRun*>& runs);

}  // namespace rig::model::effects
