#pragma once
// The effect catalogue: every term the model lab can add, built by name. Covariate
// candidates are discovered from the runs: numeric metadata and extra channels the model
// does not use (not IOP or velocity, not ids, not the rig's own commands).
//
// Every entry is an effect family (see effects/family_term.hpp): make(NAME) fits each of its
// forms on the catalogue's runs over the model's own effects (and set_baseline's) and
// returns the entry in the form with the lowest BIC; the choice is kept for later calls.
// A cross-validation fold uses on_runs(its training runs): a catalogue of its own whose
// forms and covariate standardisation are chosen on those runs alone.
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "effect_term.hpp"
#include "effects/covariate_range.hpp"
#include "force_model.hpp"

namespace rig::model {
namespace effects {
struct SelectionBaseline;
}

class EffectCatalogue {
 public:
  EffectCatalogue(const ForceModel& model, const std::vector<const PreparedRun*>& runs);

  // Throws std::invalid_argument naming the unknown effect and listing the known ones.
  // Families come in their best form for the runs (selected once, then remembered).
  std::unique_ptr<EffectTerm> make(const std::string& name) const;
  // The entry in a given form (by its name, e.g. "viscous"); throws naming the known forms.
  std::unique_ptr<EffectTerm> make_form(const std::string& name, const std::string& form) const;
  // A saved effect: the form whose parameter names the setting carries (most names wins).
  std::unique_ptr<EffectTerm> make_saved(const EffectSetting& setting) const;
  // Effects taken as part of the baseline when forms are selected (diagnose --with); call
  // before the first make().
  void set_baseline(const std::vector<std::string>& with) { with_ = with; }
  // Off: make() returns each family's default form (the lab's form before families).
  void set_form_selection(bool on) { select_forms_ = on; }
  // Every candidate for these runs: the built-in catalogue, covariate:KEY, and user:NAME for
  // the model's candidate terms (its own user terms are always in the model).
  std::vector<std::string> candidates() const;
  static const std::vector<std::string>& builtin_names();
  // The runs forms are chosen on and covariates standardised over.
  const std::vector<const PreparedRun*>& runs() const { return runs_; }
  const ForceModel& model() const { return *model_; }
  // The same catalogue (model, baseline, form selection on or off) on a subset of the runs,
  // e.g. a fold's training runs: its forms and covariate centres and spreads are chosen on
  // `subset` only. Cached per subset of this catalogue's own runs, so the baseline and every
  // candidate of a diagnosis share a fold's choices; runs not among them (a run's time
  // blocks) get a fresh, uncached catalogue.
  std::shared_ptr<const EffectCatalogue> on_runs(
      const std::vector<const PreparedRun*>& subset) const;

 private:
  std::unique_ptr<EffectTerm> make_in_form(const std::string& name, int form) const;  // -1: default
  std::unique_ptr<EffectTerm> selected(const std::string& name) const;

  struct SelectionCache {
    std::mutex mutex;
    std::once_flag baseline_once;
    std::shared_ptr<const effects::SelectionBaseline> baseline;  // fitted once for all families
    std::map<std::string, std::pair<int, std::string>> chosen;   // name -> form, note
    std::map<std::vector<bool>, std::shared_ptr<const EffectCatalogue>>
        on_subsets;  // key: which of runs_ are in it
  };
  std::shared_ptr<EffectCatalogue> with_settings_on(
      const std::vector<const PreparedRun*>& subset) const;
  const ForceModel* model_;
  std::vector<const PreparedRun*> runs_;
  std::vector<std::string> with_;
  bool select_forms_ = true;
  std::shared_ptr<SelectionCache> cache_ = std::make_shared<SelectionCache>();
  std::vector<std::string> covariates_;
  std::vector<effects::CovariateRange>
      covariate_stats_;  // mean, spread across runs; the values seen
};

// The model's own added effects (from its file) with their saved parameters.
struct SavedEffect {
  std::unique_ptr<EffectTerm> term;
  std::vector<double> params;
};
std::vector<SavedEffect> saved_effects(const ForceModel& model, const EffectCatalogue& catalogue);

}  // namespace rig::model
