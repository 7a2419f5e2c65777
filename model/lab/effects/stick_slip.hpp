#pragma once
// stick_slip: the blade tears the cornea in periodic steps during the cutting phase. Tearing
// starts at the puncture, so the pattern is locked to x_pi: Fourier coefficients and the
// tearing period are shared by all runs; zero outside the cutting phase. The family: 3
// harmonics (sawtooth-like tears), a sine, or tears whose period follows the cutting speed
// as a power law (velocity weakening or strengthening of the tear), or a period that grows
// or shrinks along the cut, p exp(g d) d mm past the puncture (the cornea thickens towards
// the limbus), each of the last two with each eye's own amplitude and phase (its own
// puncture and toughness); or tears of any length, read off the force's own releases
// (tear_releases.hpp): after each drop the force builds back linearly over up to a tear's
// length, `tear_length` (v / 2 mm/s)^speed_exponent (tears are longer where the blade cuts
// faster), each eye with its own amplitude. No level of its own: a constant from the first
// release on would take up the eye's own cutting force (effect-free draw 360021 gained 32 %
// across eyes so, and nothing within them). Aperiodic tearing has no period a held-out run
// could be scored on, but the travel since its last release is in the force record before
// each sample, so that form predicts a held-out run's samples from its past.
#include "family_term.hpp"

namespace rig::model::effects {

class StickSlip final : public FamilyTerm {
 public:
  enum Form { kThreeHarmonics = 0, kSine, kSpeedScaled, kReleased, kGrowing };
  explicit StickSlip(int form = kThreeHarmonics) : FamilyTerm(form_names(), form) {}
  static const std::vector<std::string>& form_names();
  std::string name() const override { return "stick_slip"; }
  std::string meaning() const override {
    return "periodic tearing (stick-slip) while the blade cuts";
  }
  std::vector<ParamSpec> shared_params() const override;
  std::vector<std::vector<double>> starts() const override;
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  int linear_columns() const override { return form_ == kReleased ? 1 : 2 * harmonics(); }
  bool per_run_coefficients() const override {
    return form_ == kSpeedScaled || form_ == kReleased || form_ == kGrowing;
  }
  int run_parameters(const PreparedRun& run) const override;
  bool identifiable(const EvidenceInput& fitted, std::string& why_not) const override;
  void design(const SampleView& s, const double* p, double* row) const override;
  std::string evidence(const EvidenceInput& in) const override;
  std::string released_evidence(const EvidenceInput& in) const;
  int harmonics() const { return form_ == kSine ? 1 : 3; }
  // The tearing period at this cutting speed [mm].
  double period_mm(double velocity_mm_s, const double* p) const;
  // Tears cut `past_mm` past the puncture when the period changes along the cut [cycles].
  static double growing_cycles(double past_mm, const double* p);
};

}  // namespace rig::model::effects
