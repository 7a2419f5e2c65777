#include "stick_slip.hpp"

#include "effect_util.hpp"

namespace rig::model::effects {

std::vector<std::vector<double>> StickSlip::starts() const {
  std::vector<std::vector<double>> out;
  for (double period = 0.08; period <= 1.6; period *= 1.02) out.push_back({period});
  return out;
}

bool StickSlip::applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const {
  for (const PreparedRun* r : runs) {
    if (r->seg.punctured && r->seg.x_c_mm - r->seg.x_pi_mm > 0.5) return true;
  }
  why_not = "no run has a cutting phase longer than 0.5 mm";
  return false;
}

void StickSlip::design(const SampleView& s, const double* p, double* row) const {
  if (!s.cutting) {
    for (int c = 0; c < 2 * kHarmonics; ++c) row[c] = 0.0;
    return;
  }
  fourier((s.x_mm - s.x_pi_mm) / p[0], kHarmonics, row);
}

std::string StickSlip::evidence(const EvidenceInput& in) const {
  return format("during the cutting phase the residual repeats every %.3f mm from the puncture on (periodic tearing)", in.shared[0]);
}

}  // namespace rig::model::effects
