#pragma once
// stress_relaxation: while the blade is held at depth the tissue relaxes, F_hold *= 1 - g(t),
// t the time in the hold; the withdrawn tissue stays as relaxed as the hold left it. The
// family covers the relaxation spectra of soft tissue:
//   stretched exponential (KWW)  g = r (1 - exp(-(t/tau)^beta))
//   one exponential              g = r (1 - exp(-t/tau))                 (standard linear solid)
//   two-term Prony               g = r1 (1 - exp(-t/tau1)) + r2 (1 - exp(-t/tau2))
//   power law (fractional)       g = 1 - (1 + t/t0)^-n
// Stops on the way in relax alike; moving on, the tissue ahead reloads linearly over a
// fitted advance `reload` [mm] (the relaxed fraction falls to 0 over it).
// Where the model predicts no force during a hold (the hold lies outside what it describes),
// the hold relaxes from the force measured when it began (mean over its first 20 ms).
// Every form starts from a grid on its time constants and amplitudes (an amplitude of 0
// would leave the time constants without a gradient).
#include <atomic>

#include "family_term.hpp"

namespace rig::model::effects {

class StressRelaxation final : public FamilyTerm {
 public:
  enum Form { kStretched = 0, kOneExponential, kProny, kPowerLaw };
  explicit StressRelaxation(int form = kStretched);
  static const std::vector<std::string>& form_names();
  std::string name() const override { return "stress_relaxation"; }
  std::string meaning() const override {
    return "tissue force decays while the blade is held (viscoelastic relaxation)";
  }
  std::vector<ParamSpec> shared_params() const override;
  std::vector<std::vector<double>> starts() const override;
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  double add(const SampleView& s, const double* p, double force_N) const override;
  std::string evidence(const EvidenceInput& in) const override;
  std::string uninformed_because(std::size_t k, const EvidenceInput& in) const override;
  // Fraction of the force lost after t seconds in the hold.
  double decayed(double t_s, const double* p) const;

 private:
  std::vector<ParamSpec> decay_params() const;     // shared_params() without `reload`
  int reload_index() const;                        // where `reload` is in the shared parameters
  mutable std::atomic<bool> model_silent_{false};  // some hold lay where the model has no force
};

}  // namespace rig::model::effects
