#pragma once
// iop_stiffness: the pre-cut stiffness of the cornea (toe a and slope b of Eq. 1) rises
// with IOP: a, b *= exp(k1 dP + k2 dP^2), dP = IOP - 15 mmHg.
#include "effect_term.hpp"

namespace rig::model::effects {

class IopStiffness final : public EffectTerm {
 public:
  std::string name() const override { return "iop_stiffness"; }
  std::string meaning() const override { return "pre-cut stiffness depends on intraocular pressure"; }
  std::vector<ParamSpec> shared_params() const override {
    return {{"k1", "1/mmHg", 0.0, -0.5, 0.5}, {"k2", "1/mmHg^2", 0.0, -0.2, 0.2}};
  }
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  void adjust_model(const PreparedRun& run, const double* p, ContinuousParams& model) const override;
  std::string evidence(const EvidenceInput& in) const override;
};

}  // namespace rig::model::effects
