#pragma once
// stick_slip: the blade tears the cornea in periodic steps during the cutting phase. Tearing
// starts at the puncture, so the pattern is locked to x_pi: Fourier coefficients and the
// tearing period are shared by all runs; zero outside the cutting phase. The family: 3
// harmonics (sawtooth-like tears), a sine, or tears whose period follows the cutting speed
// as a power law (velocity weakening or strengthening of the tear), each eye with its own
// amplitude and phase (its own puncture and toughness). Aperiodic tearing (random events)
// predicts nothing a held-out run could be scored on, so it is not a term: the diagnosis
// sees it as residual structure in the cutting phase.
#include "family_term.hpp"

namespace rig::model::effects {

class StickSlip final : public FamilyTerm {
 public:
  enum Form { kThreeHarmonics = 0, kSine, kSpeedScaled };
  explicit StickSlip(int form = kThreeHarmonics) : FamilyTerm(form_names(), form) {}
  static const std::vector<std::string>& form_names();
  std::string name() const override { return "stick_slip"; }
  std::string meaning() const override { return "periodic tearing (stick-slip) while the blade cuts"; }
  std::vector<ParamSpec> shared_params() const override;
  std::vector<std::vector<double>> starts() const override;
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  int linear_columns() const override { return 2 * harmonics(); }
  bool per_run_coefficients() const override { return form_ == kSpeedScaled; }
  void design(const SampleView& s, const double* p, double* row) const override;
  std::string evidence(const EvidenceInput& in) const override;
  int harmonics() const { return form_ == kSine ? 1 : 3; }
  double period_mm(double velocity_mm_s, const double* p) const;  // the tearing period at this cutting speed [mm]
};

}  // namespace rig::model::effects
