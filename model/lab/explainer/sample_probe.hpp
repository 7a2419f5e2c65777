#pragma once
// An effect term that adds nothing and records what a user term would see at each sample
// (the SampleView and the model's tissue force so far), so that the explainer's features are
// computed from exactly the values a user term is evaluated on.
#include <vector>

#include "effect_term.hpp"

namespace rig::model::explainer {

struct ProbedSample {
  double x_mm = 0.0, t_s = 0.0, velocity_mm_s = 0.0, iop_mmHg = 0.0;
  double force_N = 0.0;  // the model's tissue force (F of a user term)
  double inserted_mm = 0.0, hold_s = 0.0;
  Phase phase = Phase::kApproach;
  std::size_t i = 0;  // sample index in the run
};

class SampleProbe final : public EffectTerm {
 public:
  std::string name() const override { return "probe"; }
  std::string meaning() const override { return "records the samples a user term sees"; }
  double add(const SampleView& s, const double* p, double force_N) const override;
  std::string evidence(const EvidenceInput& in) const override;

  // Takes the samples recorded since the last call, in evaluation order.
  std::vector<ProbedSample> take() const;

 private:
  mutable std::vector<ProbedSample> samples_;
};

}  // namespace rig::model::explainer
