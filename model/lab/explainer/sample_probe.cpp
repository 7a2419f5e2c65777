#include "sample_probe.hpp"

#include <utility>

namespace rig::model::explainer {

double SampleProbe::add(const SampleView& s, const double* /*p*/, double force_N) const {
  samples_.push_back({s.x_mm, s.t_s, s.velocity_mm_s, s.run->iop_mmHg, force_N, s.inserted_mm,
                      s.hold_s, s.phase, s.i});
  return 0.0;
}

std::string SampleProbe::evidence(const EvidenceInput& /*in*/) const {
  return "";
}

std::vector<ProbedSample> SampleProbe::take() const {
  return std::exchange(samples_, {});
}

}  // namespace rig::model::explainer
