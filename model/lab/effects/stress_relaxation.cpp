#include "stress_relaxation.hpp"

#include "effect_util.hpp"

namespace rig::model::effects {

bool StressRelaxation::applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const {
  for (const PreparedRun* r : runs) {
    const auto& s = r->seg;
    if (s.hold_end > s.hold_begin && r->data->t_s[s.hold_end - 1] - r->data->t_s[s.hold_begin] >= 0.5) return true;
  }
  why_not = "no run holds at depth for 0.5 s or more";
  return false;
}

double StressRelaxation::add(const SampleView& s, const double* p, double force_N) const {
  if (s.hold_s <= 0.0) return 0.0;  // in the hold, and after it while the blade withdraws
  return -p[0] * (1.0 - std::exp(-std::pow(s.hold_s / p[1], p[2]))) * force_N;
}

std::string StressRelaxation::evidence(const EvidenceInput& in) const {
  return format("during holds the force decays by %.0f %% with a time constant of %.2f s (stretch exponent %.2f)",
                100.0 * in.shared[0], in.shared[1], in.shared[2]);
}

}  // namespace rig::model::effects
