#pragma once
// covariate:<key>: a run covariate (numeric metadata, or an extra channel) the model does
// not use scales the tissue force, separately before and after the puncture:
// F *= exp(c1 z + c2 z^2) (pre-cut), exp(c3 z + c4 z^2) (after), z = (value - mean) / spread.
#include "effect_term.hpp"

namespace rig::model::effects {

class CovariateScaling final : public EffectTerm {
 public:
  CovariateScaling(std::string key, double mean, double spread) : key_(std::move(key)), mean_(mean), spread_(spread) {}
  std::string name() const override { return "covariate:" + key_; }
  std::string meaning() const override { return "run covariate '" + key_ + "' scales the tissue force"; }
  std::vector<ParamSpec> shared_params() const override {
    return {{"c1", "1", 0.0, -2.0, 2.0}, {"c2", "1", 0.0, -1.0, 1.0}, {"c3", "1", 0.0, -2.0, 2.0}, {"c4", "1", 0.0, -1.0, 1.0}};
  }
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  double scale(const SampleView& s, const double* p) const override;
  std::string evidence(const EvidenceInput& in) const override;
  const std::string& key() const { return key_; }
  double mean() const { return mean_; }
  double spread() const { return spread_; }

 private:
  std::string key_;
  double mean_;
  double spread_;
};

}  // namespace rig::model::effects
