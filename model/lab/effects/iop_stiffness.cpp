#include "iop_stiffness.hpp"

#include <algorithm>

#include "effect_util.hpp"

namespace rig::model::effects {

bool IopStiffness::applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const {
  double lo = 1e9, hi = -1e9;
  for (const PreparedRun* r : runs) {
    if (!r->iop_known) continue;
    lo = std::min(lo, r->iop_mmHg);
    hi = std::max(hi, r->iop_mmHg);
  }
  if (hi - lo < 0.9) why_not = "runs do not span at least 1 mmHg of IOP";
  return hi - lo >= 0.9;
}

void IopStiffness::adjust_model(const PreparedRun& run, const double* p, ContinuousParams& model) const {
  if (!run.iop_known) return;
  const double dp = run.iop_mmHg - 15.0;
  const double factor = std::exp(p[0] * dp + p[1] * dp * dp);
  model.a *= factor;
  model.b *= factor;
}

std::string IopStiffness::evidence(const EvidenceInput& in) const {
  double lo = 1e9, hi = -1e9;
  for (const PreparedRun* r : in.runs) lo = std::min(lo, r->iop_mmHg), hi = std::max(hi, r->iop_mmHg);
  const double dp = hi - 15.0;
  const double change = std::exp(in.shared[0] * dp + in.shared[1] * dp * dp) - 1.0;
  return format("pre-cut stiffness changes %+.1f %% per mmHg (%+.1f %% at %.0f mmHg against 15 mmHg)", 100.0 * in.shared[0],
                100.0 * change, hi);
}

}  // namespace rig::model::effects
