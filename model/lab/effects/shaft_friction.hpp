#pragma once
// shaft_friction: once punctured, the blade's shaft rubs along the incision: a force that
// grows with the inserted length L past the puncture and opposes motion (dir: +1 inserting,
// 0 at rest - the hold and stops on the way in - and -1 retracting, from the phase). The
// family covers the friction laws of a blade in tissue:
//   coulomb             mu L dir                      (constant per inserted length)
//   saturating          mu (1 - exp(-kappa L))/kappa dir   (the shaft's own length)
//   viscous             eta L v                       (v the signed velocity [mm/s])
//   coulomb + viscous   (mu dir + eta v) L
//   asymmetric          L (mu_in inserting, -mu_out retracting)
//   static breakaway    L dir (mu + mu_s exp(-|v|/v_s))   (Stribeck: more at rest/reversal)
//   held at rest        mu_held L (+1 until the retraction, -1 in it)   (presliding: a stop keeps
//   the load) presliding          mu L (1 - 2 min(1, d / grip)), d = furthest x - x  (an
//   elastic-plastic grip
//                       that reverses over a length: a Jenkins element, not Dahl's exponential)
#include "family_term.hpp"

namespace rig::model::effects {

class ShaftFriction final : public FamilyTerm {
 public:
  enum Form {
    kCoulomb = 0,
    kSaturating,
    kViscous,
    kCoulombViscous,
    kAsymmetric,
    kBreakaway,
    kHeldAtRest,
    kPresliding
  };
  explicit ShaftFriction(int form = kSaturating);
  static const std::vector<std::string>& form_names();
  std::string name() const override { return "shaft_friction"; }
  std::string meaning() const override {
    return "friction along the inserted blade, growing with inserted length, opposing motion";
  }
  std::vector<ParamSpec> shared_params() const override;
  std::vector<std::vector<double>> starts() const override;
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  double add(const SampleView& s, const double* p, double force_N) const override;
  std::string evidence(const EvidenceInput& in) const override;
};

}  // namespace rig::model::effects
