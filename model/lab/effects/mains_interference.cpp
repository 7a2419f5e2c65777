#include "mains_interference.hpp"

#include <algorithm>

#include "effect_util.hpp"

namespace rig::model::effects {

bool MainsInterference::applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const {
  for (const PreparedRun* r : runs) {
    const double span = r->data->t_s.back() - r->data->t_s.front();
    const double rate = static_cast<double>(r->size()) / std::max(span, 1e-9);
    if (rate < 150.0) {
      why_not = "sampling below 150 Hz cannot show 50/60 Hz";
      return false;
    }
  }
  return true;
}

void MainsInterference::design(const SampleView& s, const double* p, double* row) const {
  fourier(s.t_s * p[0], kHarmonics, row);
}

std::string MainsInterference::evidence(const EvidenceInput& in) const {
  return format("the residual oscillates at %.2f Hz in time (amplitude up to %.4f N), the mains frequency",
                in.shared[0], largest_amplitude(in.run_coefficients));
}

}  // namespace rig::model::effects
