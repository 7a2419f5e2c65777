#pragma once
// shaft_friction: once punctured, the blade's shaft rubs along the incision: a force that
// grows with the inserted length L past the puncture and opposes motion (it reverses on
// retraction): F += mu (1 - exp(-kappa L)) / kappa * direction (+1 inserting, 0 held, -1
// retracting). kappa = 0 is linear in L, kappa > 0 saturates (the shaft's own length).
#include "effect_term.hpp"

namespace rig::model::effects {

class ShaftFriction final : public EffectTerm {
 public:
  std::string name() const override { return "shaft_friction"; }
  std::string meaning() const override { return "friction along the inserted blade, growing with inserted length, opposing motion"; }
  std::vector<ParamSpec> shared_params() const override {
    return {{"mu", "N/mm", 0.0, -0.1, 0.1}, {"kappa", "1/mm", 0.0, -0.3, 3.0}};
  }
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  double add(const SampleView& s, const double* p, double force_N) const override;
  std::string evidence(const EvidenceInput& in) const override;
};

}  // namespace rig::model::effects
