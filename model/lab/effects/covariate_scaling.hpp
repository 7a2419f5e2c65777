#pragma once
// covariate:<key>: a run covariate (numeric metadata, or an extra channel) the model does
// not use scales the tissue force; z = (value - mean) / spread. The family covers where and
// how it acts:
//   per phase, quadratic     exp(c1 z + c2 z^2) before the puncture, exp(c3 z + c4 z^2) after
//   exponential, all phases  exp(c z)
//   linear, all phases       1 + c_lin z
//   after the puncture only  exp(c_cut z) once punctured, 1 before
//   before the puncture only exp(c_pre z) before the puncture, 1 after
//   moves the puncture       x_pi + xpi_1 z + xpi_2 z^2 [mm], forces unscaled
#include "family_term.hpp"

namespace rig::model::effects {

class CovariateScaling final : public FamilyTerm {
 public:
  enum Form { kPerPhase = 0, kExponential, kLinear, kAfterPuncture, kBeforePuncture, kPunctureShift };
  CovariateScaling(std::string key, double mean, double spread, int form = kPerPhase)
      : FamilyTerm(form_names(), form), key_(std::move(key)), mean_(mean), spread_(spread) {}
  static const std::vector<std::string>& form_names();
  std::string name() const override { return "covariate:" + key_; }
  std::string meaning() const override { return "run covariate '" + key_ + "' scales the tissue force or moves the puncture"; }
  std::vector<ParamSpec> shared_params() const override;
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  void adjust_model(const PreparedRun& run, const double* p, ContinuousParams& model) const override;
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
