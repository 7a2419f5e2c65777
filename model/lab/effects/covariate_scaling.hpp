#pragma once
// covariate:<key>: a run covariate (numeric metadata, or an extra channel) the model does
// not use scales the tissue force; z = (value - mean) / spread, the value held to the range
// the term was fitted on (covariate_range.hpp). The family covers where and
// how it acts:
//   per phase, quadratic     exp(c1 z + c2 z^2) before the puncture, exp(c3 z + c4 z^2) after
//   exponential, all phases  exp(c z)
//   linear, all phases       1 + c_lin z
//   after the puncture only  exp(c_cut z) once punctured, 1 before
//   before the puncture only exp(c_pre z) before the puncture, 1 after
//   moves the puncture       x_pi + xpi_1 z + xpi_2 z^2 [mm], forces unscaled
#include <algorithm>

#include "covariate_range.hpp"
#include "family_term.hpp"

namespace rig::model::effects {

class CovariateScaling final : public FamilyTerm {
 public:
  enum Form {
    kPerPhase = 0,
    kExponential,
    kLinear,
    kAfterPuncture,
    kBeforePuncture,
    kPunctureShift
  };
  CovariateScaling(std::string key, const CovariateRange& range, int form = kPerPhase)
      : FamilyTerm(form_names(), form), key_(std::move(key)), range_(range) {}
  static const std::vector<std::string>& form_names();
  std::string name() const override { return "covariate:" + key_; }
  std::string meaning() const override {
    return "run covariate '" + key_ + "' scales the tissue force or moves the puncture";
  }
  std::vector<ParamSpec> shared_params() const override;
  std::vector<std::vector<double>> starts() const override;
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  void adjust_model(const PreparedRun& run, const double* p,
                    ContinuousParams& model) const override;
  double scale(const SampleView& s, const double* p) const override;
  std::string evidence(const EvidenceInput& in) const override;
  EyeDof eye_level_params(const double* p) const override;
  std::vector<std::size_t> puncture_regressors(const PreparedRun& run,
                                               std::vector<double>& values) const override;
  // A scaling form acts on whole runs; moving the puncture reaches past an eye's own shift.
  bool judged_on_unseen_eyes_alone() const override { return form_ != kPunctureShift; }
  const std::string& key() const { return key_; }
  const CovariateRange& range() const { return range_; }

 private:
  double z_of(double value) const {
    return (std::clamp(value, range_.low - range_.reach, range_.high + range_.reach) -
            range_.mean) /
           range_.spread;
  }
  std::string key_;
  CovariateRange range_;
};

}  // namespace rig::model::effects
