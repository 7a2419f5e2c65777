#pragma once
// rate_dependence: tissue force depends on the keratome velocity (viscoelastic cornea).
// F_tissue *= exp(b1 u + b2 u^2), u = ln(v / v_ref): a power law when b2 = 0, and close to
// a linear law over the lab's 0.5-4 mm/s.
#include "effect_term.hpp"

namespace rig::model::effects {

class RateDependence final : public EffectTerm {
 public:
  explicit RateDependence(double reference_velocity_mm_s) : v_ref_(reference_velocity_mm_s) {}
  std::string name() const override { return "rate_dependence"; }
  std::string meaning() const override { return "tissue force grows with keratome velocity (viscoelasticity)"; }
  std::vector<ParamSpec> shared_params() const override {
    return {{"b1", "1 per ln(v)", 0.0, -2.0, 2.0}, {"b2", "1 per ln(v)^2", 0.0, -2.0, 2.0}};
  }
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  double scale(const SampleView& s, const double* p) const override;
  std::string evidence(const EvidenceInput& in) const override;

 private:
  double v_ref_;
};

}  // namespace rig::model::effects
