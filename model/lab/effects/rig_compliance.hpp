#pragma once
// rig_compliance: the load cell and keratome mount give way, so the tip lags the measured
// carriage by c1 F + c2 F^2 (a stiffening mount has c2 < 0): the model is evaluated at the
// tip, x - c1 F - c2 F^2, with F the measured force.
#include "effect_term.hpp"

namespace rig::model::effects {

class RigCompliance final : public EffectTerm {
 public:
  std::string name() const override { return "rig_compliance"; }
  std::string meaning() const override { return "the keratome tip lags the measured carriage by F/k (compliant mount)"; }
  std::vector<ParamSpec> shared_params() const override {
    return {{"c1", "mm/N", 0.0, -0.5, 3.0}, {"c2", "mm/N^2", 0.0, -10.0, 10.0}};
  }
  double x_shift(const SampleView& s, const double* p) const override;
  std::string evidence(const EvidenceInput& in) const override;
};

}  // namespace rig::model::effects
