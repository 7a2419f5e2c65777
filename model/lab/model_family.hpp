#pragma once
// A model family to fit: Eq. 1 plus a list of effect terms (owned), with starting values.
// Builds the Predictor, picks the best start of multimodal terms, runs the CV. An effect is
// never in a family twice: an extra effect the model already has is left out. In the CV each
// fold uses the same effects rebuilt on its training runs (trained_on): every family's form
// is chosen there, so a held-out run decides nothing of its fold.
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cross_validation.hpp"
#include "effect_catalogue.hpp"

namespace rig::model {

class ModelFamily {
 public:
  ModelFamily(const ForceModel& model, const EffectCatalogue& catalogue,
              const std::vector<std::string>& extra_effects);

  const Predictor& predictor() const { return *predictor_; }
  const std::vector<std::string>& effect_names() const { return names_; }
  // Start values: the model file's, with the best of each new term's starting points.
  ModelParams start(const std::vector<const PreparedRun*>& runs) const;
  // The model a fit on `runs` uses: this family with its start values when `runs` are its
  // catalogue's, else the same effects from catalogue.on_runs(runs), forms chosen on `runs`.
  TrainedModel trained_on(const std::vector<const PreparedRun*>& runs) const;
  CvResult cross_validate(const std::vector<const PreparedRun*>& runs) const;
  // Each term's form, in term order ("" for a term with a single form).
  std::vector<std::string> forms() const;
  // What eye-to-eye variation adds per sample to a prediction for an unseen eye [N^2].
  double eye_variance_N2(const FitResult& fit, const std::vector<const PreparedRun*>& runs) const;
  // The effect settings (shared parameters by name) of a fit, for a model file.
  std::vector<EffectSetting> settings(const ModelParams& params) const;
  // The user terms of the family with their fitted parameters, for the model file's [terms].
  std::vector<UserTerm> user_terms(const ModelParams& params) const;
  std::string evidence(const std::string& effect, const FitResult& fit,
                       const std::vector<const PreparedRun*>& runs) const;
  // EffectTerm::identifiable of `effect` with the parameters of `fit` (true if not in the family).
  bool identifiable(const std::string& effect, const FitResult& fit,
                    const std::vector<const PreparedRun*>& runs, std::string& why_not) const;

 private:
  // The term named `effect` and its fitted parameters, as its evidence sees them.
  std::optional<std::pair<const EffectTerm*, EvidenceInput>> fitted_term(
      const std::string& effect, const FitResult& fit,
      const std::vector<const PreparedRun*>& runs) const;
  EffectCatalogue catalogue_;       // shares its form choices and per-subset catalogues
  std::vector<std::string> extra_;  // the effects asked for beyond the model's own
  std::vector<std::unique_ptr<EffectTerm>> owned_;
  std::vector<std::string> names_;
  std::vector<std::vector<double>> saved_params_;
  std::size_t saved_count_ = 0;
  std::unique_ptr<Predictor> predictor_;
};

}  // namespace rig::model
