#pragma once
// stick_slip: the blade tears the cornea in periodic steps during the cutting phase. Tearing
// starts at the puncture, so the pattern is locked to x_pi: Fourier coefficients (3
// harmonics: sawtooth-like tears) and the tearing period are shared by all runs; zero
// outside the cutting phase.
#include "effect_term.hpp"

namespace rig::model::effects {

class StickSlip final : public EffectTerm {
 public:
  static constexpr int kHarmonics = 3;
  std::string name() const override { return "stick_slip"; }
  std::string meaning() const override { return "periodic tearing (stick-slip) while the blade cuts"; }
  std::vector<ParamSpec> shared_params() const override { return {{"period", "mm", 0.4, 0.05, 2.0}}; }
  std::vector<std::vector<double>> starts() const override;
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  int linear_columns() const override { return 2 * kHarmonics; }
  bool per_run_coefficients() const override { return false; }
  void design(const SampleView& s, const double* p, double* row) const override;
  std::string evidence(const EvidenceInput& in) const override;
};

}  // namespace rig::model::effects
