#pragma once
// mains_interference: 50/60 Hz pick-up on the force channel: per-run sine and cosine
// coefficients at a frequency shared by all runs. The family: a pure sine, 3 harmonics
// (a rectifier or transformer distorts it), or a sine whose frequency drifts slowly during
// the run (f + chirp t: the grid's frequency wanders by tenths of a hertz).
#include "family_term.hpp"

namespace rig::model::effects {

class MainsInterference final : public FamilyTerm {
 public:
  enum Form { kThreeHarmonics = 0, kSine, kChirp };
  explicit MainsInterference(int form = kThreeHarmonics) : FamilyTerm(form_names(), form) {}
  static const std::vector<std::string>& form_names();
  std::string name() const override { return "mains_interference"; }
  std::string meaning() const override { return "50/60 Hz mains pick-up on the force channel (instrument)"; }
  std::vector<ParamSpec> shared_params() const override;
  std::vector<std::vector<double>> starts() const override;
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  int linear_columns() const override { return 2 * (form_ == kThreeHarmonics ? 3 : 1); }
  void design(const SampleView& s, const double* p, double* row) const override;
  std::string evidence(const EvidenceInput& in) const override;
};

}  // namespace rig::model::effects
