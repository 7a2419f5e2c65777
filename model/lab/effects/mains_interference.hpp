#pragma once
// mains_interference: 50/60 Hz pick-up on the force channel: per-run sine and cosine
// coefficients of the fundamental and 2 harmonics at a frequency shared by all runs.
#include "effect_term.hpp"

namespace rig::model::effects {

class MainsInterference final : public EffectTerm {
 public:
  static constexpr int kHarmonics = 3;
  std::string name() const override { return "mains_interference"; }
  std::string meaning() const override { return "50/60 Hz mains pick-up on the force channel (instrument)"; }
  std::vector<ParamSpec> shared_params() const override { return {{"frequency", "Hz", 50.0, 45.0, 65.0}}; }
  std::vector<std::vector<double>> starts() const override { return {{50.0}, {60.0}}; }
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  int linear_columns() const override { return 2 * kHarmonics; }
  void design(const SampleView& s, const double* p, double* row) const override;
  std::string evidence(const EvidenceInput& in) const override;
};

}  // namespace rig::model::effects
