#pragma once
// stress_relaxation: while the blade is held at depth the tissue relaxes:
// F_hold *= 1 - r (1 - exp(-(t / tau)^beta)) (stretched exponential: beta < 1 approaches a
// power law). The withdrawn tissue stays as relaxed as the hold left it.
#include "effect_term.hpp"

namespace rig::model::effects {

class StressRelaxation final : public EffectTerm {
 public:
  std::string name() const override { return "stress_relaxation"; }
  std::string meaning() const override { return "tissue force decays while the blade is held (viscoelastic relaxation)"; }
  std::vector<ParamSpec> shared_params() const override {
    return {{"r", "1", 0.0, -1.0, 1.0}, {"tau", "s", 1.0, 0.02, 60.0}, {"beta", "1", 1.0, 0.2, 1.5}};
  }
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  double add(const SampleView& s, const double* p, double force_N) const override;
  std::string evidence(const EvidenceInput& in) const override;
};

}  // namespace rig::model::effects
