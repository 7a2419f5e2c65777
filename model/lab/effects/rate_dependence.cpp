#include "rate_dependence.hpp"

#include <algorithm>

#include "effect_util.hpp"

namespace rig::model::effects {

bool RateDependence::applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const {
  double lo = 1e9, hi = 0.0;
  for (const PreparedRun* r : runs) lo = std::min(lo, r->velocity_cmd_mm_s), hi = std::max(hi, r->velocity_cmd_mm_s);
  if (hi < lo * 1.2) why_not = "all runs at about the same velocity";
  return hi >= lo * 1.2;
}

double RateDependence::scale(const SampleView& s, const double* p) const {
  const double u = std::log(std::max(s.run->velocity_cmd_mm_s, 0.01) / v_ref_);
  return std::exp(p[0] * u + p[1] * u * u);
}

std::string RateDependence::evidence(const EvidenceInput& in) const {
  double lo = 1e9, hi = 0.0;
  for (const PreparedRun* r : in.runs) lo = std::min(lo, r->velocity_cmd_mm_s), hi = std::max(hi, r->velocity_cmd_mm_s);
  auto factor = [&](double v) {
    const double u = std::log(v / v_ref_);
    return std::exp(in.shared[0] * u + in.shared[1] * u * u);
  };
  return format("tissue force is %+.1f %% at %.2g mm/s and %+.1f %% at %.2g mm/s relative to the model's velocity",
                100.0 * (factor(lo) - 1.0), lo, 100.0 * (factor(hi) - 1.0), hi);
}

}  // namespace rig::model::effects
