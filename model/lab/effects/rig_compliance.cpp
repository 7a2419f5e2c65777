#include "rig_compliance.hpp"

#include "effect_util.hpp"

namespace rig::model::effects {

double RigCompliance::x_shift(const SampleView& s, const double* p) const {
  const double f = std::max(s.force_N, 0.0);
  return p[0] * f + p[1] * f * f;
}

std::string RigCompliance::evidence(const EvidenceInput& in) const {
  const double f = 0.2;  // a typical puncture force [N]
  const double lag = in.shared[0] * f + in.shared[1] * f * f;
  return format("the tip lags the carriage by %.3f mm at %.1f N (mount stiffness about %.2f N/mm)", lag, f,
                lag > 1e-9 ? f / lag : 0.0);
}

}  // namespace rig::model::effects
