#pragma once
// spatial_ripple: a force ripple periodic in carriage position (lead-screw pitch, nut
// wobble): per-run Fourier coefficients (3 harmonics, so sawtooth-like shapes fit too) at a
// period shared by all runs. The run's phase is its own: the screw angle at contact differs.
// Tare is taken at rest, wherever the ripple then is: each run also gets a constant offset.
#include "effect_term.hpp"

namespace rig::model::effects {

class SpatialRipple final : public EffectTerm {
 public:
  static constexpr int kHarmonics = 3;
  std::string name() const override { return "spatial_ripple"; }
  std::string meaning() const override { return "force ripple periodic in displacement, e.g. lead-screw pitch (instrument)"; }
  std::vector<ParamSpec> shared_params() const override { return {{"period", "mm", 1.0, 0.2, 5.0}}; }
  std::vector<std::vector<double>> starts() const override;
  int linear_columns() const override { return 2 * kHarmonics + 1; }  // + the offset taken in by tare
  void design(const SampleView& s, const double* p, double* row) const override;
  std::string evidence(const EvidenceInput& in) const override;
};

}  // namespace rig::model::effects
