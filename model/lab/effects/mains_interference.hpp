#pragma once
// mains_interference: 50/60 Hz pick-up on the force channel: per-run sine and cosine
// coefficients at each run's own grid frequency (its spectral line near the nominal,
// grid_line.hpp: grids run off nominal by hundredths of a hertz, which over a run slips a
// shared frequency by cycles). The family: a pure sine, 5 harmonics (rectifiers and
// transformers distort it), a sine whose frequency drifts during the run (f + chirp t), or
// a sine picked up from the motor drive, present only while the carriage moves.
#include "family_term.hpp"

namespace rig::model::effects {

class MainsInterference final : public FamilyTerm {
 public:
  enum Form { kHarmonics = 0, kSine, kChirp, kWhileMoving };
  static constexpr int kHarmonicCount = 5;
  explicit MainsInterference(int form = kHarmonics) : FamilyTerm(form_names(), form) {}
  static const std::vector<std::string>& form_names();
  std::string name() const override { return "mains_interference"; }
  std::string meaning() const override {
    return "50/60 Hz mains pick-up on the force channel (instrument)";
  }
  std::vector<ParamSpec> shared_params() const override;
  std::vector<std::vector<double>> starts() const override;
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  int linear_columns() const override { return 2 * (form_ == kHarmonics ? kHarmonicCount : 1); }
  void design(const SampleView& s, const double* p, double* row) const override;
  std::string evidence(const EvidenceInput& in) const override;

 private:
  static double run_hz(const PreparedRun& run, double p0);  // [Hz]
};

}  // namespace rig::model::effects
