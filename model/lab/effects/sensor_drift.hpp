#pragma once
// sensor_drift: the load-cell offset wanders during a run (warm-up, temperature): a
// per-run offset + slope + curvature in time, fitted on each run's own data.
#include "effect_term.hpp"

namespace rig::model::effects {

class SensorDrift final : public EffectTerm {
 public:
  std::string name() const override { return "sensor_drift"; }
  std::string meaning() const override { return "load-cell offset drifting with time during a run (instrument)"; }
  int linear_columns() const override { return 3; }
  void design(const SampleView& s, const double* p, double* row) const override;
  std::string evidence(const EvidenceInput& in) const override;
};

}  // namespace rig::model::effects
