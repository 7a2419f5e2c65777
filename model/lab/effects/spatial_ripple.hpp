#pragma once
// spatial_ripple: a force ripple periodic in carriage position (lead-screw pitch, nut
// wobble): per-run Fourier coefficients at a period shared by all runs. The run's phase is
// its own: the screw angle at contact differs. Tare is taken at rest where the run begins,
// so the ripple there is subtracted: each column is its value less its value at the run's
// first position (no free offset per run: that is drift's or tare's). The family: a pure sine (1
// harmonic), 3 harmonics (sawtooth-like shapes), or a sine whose amplitude is proportional to the
// load on the screw (the measured force: a nut's friction torque ripple grows with its axial load).
#include <limits>
#include "family_term.hpp"

namespace rig::model::effects {

class SpatialRipple final : public FamilyTerm {
 public:
  enum Form { kThreeHarmonics = 0, kSine, kWithTheLoad };
  explicit SpatialRipple(int form = kThreeHarmonics) : FamilyTerm(form_names(), form) {}
  static const std::vector<std::string>& form_names();
  std::string name() const override { return "spatial_ripple"; }
  std::string meaning() const override {
    return "force ripple periodic in displacement, e.g. lead-screw pitch (instrument)";
  }
  std::vector<ParamSpec> shared_params() const override;
  std::vector<std::vector<double>> starts() const override;
  int linear_columns() const override {
    return 2 * harmonics();
  }  // less their value where the force was tared
  void design(const SampleView& s, const double* p, double* row) const override;
  std::string evidence(const EvidenceInput& in) const override;
  // A ripple must repeat: its period seen at least kMinPeriodsSeen times over the depth the
  // runs traverse (median run). Fewer, and a sine bends to any smooth misfit of the baseline
  // (measured meat indentation: a 3.9 mm "ripple" over 6-8 mm ramps, docs/model-lab.md).
  bool identifiable(const EvidenceInput& fitted, std::string& why_not) const override;
  static constexpr double kMinPeriodsSeen = 3.0;
  int harmonics() const { return form_ == kThreeHarmonics ? 3 : 1; }
  // The columns' values where the run was tared, for one parked position [mm] and period [mm].
  struct TareColumns {
    double parked_mm = std::numeric_limits<double>::quiet_NaN();  // NaN: nothing computed yet
    double period_mm = 0.0;
    int harmonics = 0;
    double columns[6] = {};
  };
};

}  // namespace rig::model::effects
