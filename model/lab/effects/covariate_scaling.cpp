#include "covariate_scaling.hpp"

#include "effect_util.hpp"

namespace rig::model::effects {

bool CovariateScaling::applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const {
  for (const PreparedRun* r : runs) {
    if (!r->covariate(key_, 0)) {
      why_not = "'" + key_ + "' missing in " + r->label();
      return false;
    }
  }
  if (spread_ <= 0.0) why_not = "'" + key_ + "' does not vary";
  return spread_ > 0.0;
}

double CovariateScaling::scale(const SampleView& s, const double* p) const {
  const double z = (s.run->covariate(key_, s.i).value_or(mean_) - mean_) / spread_;
  return s.after_puncture ? std::exp(p[2] * z + p[3] * z * z) : std::exp(p[0] * z + p[1] * z * z);
}

std::string CovariateScaling::evidence(const EvidenceInput& in) const {
  const double per_unit_pre = 100.0 * in.shared[0] / spread_;
  const double per_unit_post = 100.0 * in.shared[2] / spread_;
  return format("tissue force changes %+.1f %% per unit of ", per_unit_pre) + key_ +
         format(" before the puncture and %+.1f %% per unit after it (runs span %.3g +- %.3g)", per_unit_post, mean_, spread_);
}

}  // namespace rig::model::effects
