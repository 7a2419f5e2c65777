#include "sensor_drift.hpp"

#include "effect_util.hpp"

namespace rig::model::effects {

void SensorDrift::design(const SampleView& s, const double* /*p*/, double* row) const {
  const double t = s.t_s / 10.0;  // scaled for conditioning
  row[0] = 1.0;
  row[1] = t;
  row[2] = t * t;
}

std::string SensorDrift::evidence(const EvidenceInput& in) const {
  double worst = 0.0, rate = 0.0;
  for (std::size_t r = 0; r < in.runs.size() && r < in.run_coefficients.size(); ++r) {
    const auto& c = in.run_coefficients[r];
    if (c.size() < 3) continue;
    const double span = in.runs[r]->data->t_s.back() / 10.0;
    const double change = std::abs(c(1) * span + c(2) * span * span);
    if (change > worst) worst = change, rate = change / (span * 10.0);
  }
  return format("the force offset moves by up to %.4f N within a run (about %.2f mN/s), differently in every run",
                worst, rate * 1e3);
}

}  // namespace rig::model::effects
