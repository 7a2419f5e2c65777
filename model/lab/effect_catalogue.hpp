#pragma once
// The effect catalogue: every term the model lab can add, built by name. Covariate
// candidates are discovered from the runs: numeric metadata and extra channels the model
// does not use (not IOP or velocity, not ids, not the rig's own commands).
#include <memory>
#include <string>
#include <vector>

#include "effect_term.hpp"
#include "force_model.hpp"

namespace rig::model {

class EffectCatalogue {
 public:
  EffectCatalogue(const ForceModel& model, const std::vector<const PreparedRun*>& runs);

  // Throws std::invalid_argument naming the unknown effect and listing the known ones.
  std::unique_ptr<EffectTerm> make(const std::string& name) const;
  // Every candidate for these runs: the built-in catalogue, covariate:KEY, and user:NAME for
  // the model's candidate terms (its own user terms are always in the model).
  std::vector<std::string> candidates() const;
  static const std::vector<std::string>& builtin_names();

 private:
  const ForceModel* model_;
  std::vector<std::string> covariates_;
  std::vector<std::pair<double, double>> covariate_stats_;  // mean, spread across runs
};

// The model's own added effects (from its file) with their saved parameters.
struct SavedEffect {
  std::unique_ptr<EffectTerm> term;
  std::vector<double> params;
};
std::vector<SavedEffect> saved_effects(const ForceModel& model, const EffectCatalogue& catalogue);

}  // namespace rig::model
