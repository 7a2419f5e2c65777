#include "model_family.hpp"

#include <algorithm>
#include <cmath>

#include "effects/covariate_scaling.hpp"
#include "effects/user_expression.hpp"

namespace rig::model {

ModelFamily::ModelFamily(const ForceModel& model, const EffectCatalogue& catalogue,
                         const std::vector<std::string>& extra)
    : catalogue_(catalogue), extra_(extra) {
  for (SavedEffect& saved : saved_effects(model, catalogue)) {
    names_.push_back(saved.term->name());
    saved_params_.push_back(saved.params);
    owned_.push_back(std::move(saved.term));
  }
  saved_count_ = owned_.size();
  for (const std::string& name : extra) {
    if (std::find(names_.begin(), names_.end(), name) != names_.end()) continue;
    owned_.push_back(catalogue.make(name));
    names_.push_back(owned_.back()->name());
  }
  std::vector<const EffectTerm*> terms;
  for (const auto& t : owned_) terms.push_back(t.get());
  predictor_ = std::make_unique<Predictor>(model, terms);
}

ModelParams ModelFamily::start(const std::vector<const PreparedRun*>& runs) const {
  ModelParams p = predictor_->initial_params();
  for (std::size_t k = 0; k < saved_count_; ++k) p.shared[k] = saved_params_[k];
  for (std::size_t k = saved_count_; k < owned_.size(); ++k) {
    const auto starts = owned_[k]->starts();
    if (starts.size() < 2) continue;
    const Fitter scorer(*predictor_, runs);
    const bool fitted = owned_[k]->fit_each_start();
    double best = INFINITY;  // score each start by the fit-row error with everything else fixed
    for (const auto& candidate : starts) {  // ... or after a short fit from it (fit_each_start)
      ModelParams trial = p;
      trial.shared[k] = candidate;
      const double error =
          fitted ? scorer.fit(trial, kStartProbeEvaluations).rmse_N : scorer.sse(trial);
      if (error < best) best = error, p.shared[k] = candidate;
    }
  }
  return p;
}

std::vector<std::string> ModelFamily::forms() const {
  std::vector<std::string> out;
  for (const auto& term : owned_) out.push_back(term->form());
  return out;
}

TrainedModel ModelFamily::trained_on(const std::vector<const PreparedRun*>& runs) const {
  if (runs == catalogue_.runs()) {
    // Not owned: this family outlives the cross-validation that asks.
    return {std::shared_ptr<const Predictor>(std::shared_ptr<const Predictor>(), predictor_.get()),
            start(runs), forms()};
  }
  const std::shared_ptr<const EffectCatalogue> catalogue = catalogue_.on_runs(runs);
  const auto family = std::make_shared<const ModelFamily>(catalogue->model(), *catalogue, extra_);
  return {std::shared_ptr<const Predictor>(family, &family->predictor()), family->start(runs),
          family->forms()};
}

CvResult ModelFamily::cross_validate(const std::vector<const PreparedRun*>& runs) const {
  return model::cross_validate(runs, [this](const std::vector<const PreparedRun*>& training) {
    return trained_on(training);
  });
}

double ModelFamily::eye_variance_N2(const FitResult& fit,
                                    const std::vector<const PreparedRun*>& runs) const {
  return model::eye_variance_N2(*predictor_, runs, fit.params, fit.eye_spread);
}

std::vector<EffectSetting> ModelFamily::settings(const ModelParams& params) const {
  std::vector<EffectSetting> out;
  for (std::size_t k = 0; k < owned_.size(); ++k) {
    if (names_[k].rfind("user:", 0) == 0) continue;  // user terms stay in [terms]
    EffectSetting setting{names_[k], {}};
    const auto specs = owned_[k]->shared_params();
    for (std::size_t i = 0; i < specs.size(); ++i)
      setting.params[specs[i].name] = params.shared[k][i];
    if (const auto* cov = dynamic_cast<const effects::CovariateScaling*>(owned_[k].get())) {
      setting.params["mean"] = cov->range().mean;
      setting.params["spread"] = cov->range().spread;
      if (std::isfinite(cov->range().low)) setting.params["low"] = cov->range().low;
      if (std::isfinite(cov->range().high)) setting.params["high"] = cov->range().high;
      if (cov->range().reach > 0.0) setting.params["reach"] = cov->range().reach;
    }
    out.push_back(std::move(setting));
  }
  return out;
}

std::vector<UserTerm> ModelFamily::user_terms(const ModelParams& params) const {
  std::vector<UserTerm> out;
  for (std::size_t k = 0; k < owned_.size(); ++k) {
    if (const auto* user = dynamic_cast<const effects::UserExpression*>(owned_[k].get()))
      out.push_back(user->with_params(params.shared[k].data()));
  }
  return out;
}

std::optional<std::pair<const EffectTerm*, EvidenceInput>> ModelFamily::fitted_term(
    const std::string& effect, const FitResult& fit,
    const std::vector<const PreparedRun*>& runs) const {
  int column = 0;
  for (std::size_t k = 0; k < owned_.size(); ++k) {
    const int columns = owned_[k]->linear_columns();
    if (names_[k] == effect) {
      EvidenceInput in{fit.params.shared[k].data(), runs, {}};
      for (const auto& c : fit.run_coefficients) {
        in.run_coefficients.push_back(columns > 0 && c.size() >= column + columns
                                          ? Eigen::VectorXd(c.segment(column, columns))
                                          : Eigen::VectorXd());
      }
      return std::make_pair(owned_[k].get(), std::move(in));
    }
    column += columns;
  }
  return std::nullopt;
}

std::string ModelFamily::evidence(const std::string& effect, const FitResult& fit,
                                  const std::vector<const PreparedRun*>& runs) const {
  const auto term = fitted_term(effect, fit, runs);
  return term ? term->first->evidence(term->second) : "";
}

bool ModelFamily::identifiable(const std::string& effect, const FitResult& fit,
                               const std::vector<const PreparedRun*>& runs,
                               std::string& why_not) const {
  const auto term = fitted_term(effect, fit, runs);
  return !term || term->first->identifiable(term->second, why_not);
}

}  // namespace rig::model
