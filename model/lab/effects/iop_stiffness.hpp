#pragma once
// iop_stiffness: the pre-cut stiffness of the cornea (toe a and slope b of Eq. 1) depends
// on IOP, dP = IOP - 15 mmHg. The family covers the laws of a pressurised shell:
//   exponential            a, b *= exp(k dP)
//   exponential-quadratic  a, b *= exp(k1 dP + k2 dP^2)
//   linear                 a, b *= 1 + k_lin dP
//   saturating             a, b *= 1 + A tanh(dP / P0)
//   shorter toe            x1 -= s dP: the pressure pre-stretches the cornea, so the blade
//                          starts further along its stiffening curve (the same curve, entered
//                          later), not on a stiffer one
#include "family_term.hpp"

namespace rig::model::effects {

class IopStiffness final : public FamilyTerm {
 public:
  enum Form { kExponential = 0, kExponentialQuadratic, kLinear, kSaturating, kShorterToe };
  explicit IopStiffness(int form = kExponentialQuadratic) : FamilyTerm(form_names(), form) {}
  static const std::vector<std::string>& form_names();
  std::string name() const override { return "iop_stiffness"; }
  std::string meaning() const override {
    return "pre-cut stiffness depends on intraocular pressure";
  }
  std::vector<ParamSpec> shared_params() const override;
  std::vector<std::vector<double>> starts() const override;
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  void adjust_model(const PreparedRun& run, const double* p,
                    ContinuousParams& model) const override;
  std::string evidence(const EvidenceInput& in) const override;
  EyeDof eye_level_params(const double* p) const override;
  double factor(double dp_mmHg, const double* p) const;
  // End of the toe region at dP [mm], from the model's x1 (moves in the "shorter toe" form only).
  double toe_end_mm(double dp_mmHg, const double* p, double x1_mm) const;
};

}  // namespace rig::model::effects
