#pragma once
// rate_dependence: tissue force depends on the keratome velocity v (viscoelastic cornea),
// relative to the model's velocity v_ref. The family covers the laws used for soft tissue:
//   power law           F *= (v/v_ref)^n
//   log-quadratic       F *= exp(b1 u + b2 u^2), u = ln(v/v_ref)   (curved power law)
//   linear              F *= 1 + c (v - v_ref)
//   saturating          F *= (1 + A h(v)) / (1 + A h(v_ref)), h(v) = v / (v + v_c)   (Carreau-like)
// at the run's insertion velocity while the blade advances; every form also fits where it
// acts: the share `at_rest` of the change that remains where the blade stands (stops, the
// hold) or withdraws, and the share `before_puncture` before the cut begins (0: a viscous
// cutting resistance, 1: a stiffening of the whole tissue).
#include "family_term.hpp"

namespace rig::model::effects {

class RateDependence final : public FamilyTerm {
 public:
  enum Form { kPowerLaw = 0, kLogQuadratic, kLinear, kSaturating };
  explicit RateDependence(double reference_velocity_mm_s, int form = kLogQuadratic)
      : FamilyTerm(form_names(), form), v_ref_(reference_velocity_mm_s) {}
  static const std::vector<std::string>& form_names();
  std::string name() const override { return "rate_dependence"; }
  std::string meaning() const override {
    return "tissue force grows with keratome velocity (viscoelasticity)";
  }
  std::vector<ParamSpec> shared_params() const override;
  std::vector<std::vector<double>> starts() const override;
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  double scale(const SampleView& s, const double* p) const override;
  std::string evidence(const EvidenceInput& in) const override;
  EyeDof eye_level_params(const double* p) const override;
  double factor(double velocity_mm_s, const double* p) const;

 private:
  std::vector<ParamSpec> law_params() const;  // the law's own, without where it acts
  int law_param_count() const;
  double v_ref_;
};

}  // namespace rig::model::effects
