#pragma once
// A researcher's own term, written as an expression in the model file ([terms.NAME]) and
// evaluated with muParser. Variables: x [mm], t [s], v [mm/s], P [mmHg], F (the model's
// tissue force so far) [N], L (inserted length past the puncture) [mm], th (time in hold)
// [s]; its parameters are fitted like any shared parameter. The term is added in its phase:
// insertion, precut, cutting (after the puncture), hold, retraction or all.
#include <muParser.h>

#include <map>
#include <memory>

#include "effect_term.hpp"

namespace rig::model::effects {

class UserExpression final : public EffectTerm {
 public:
  explicit UserExpression(const UserTerm& term);  // throws ModelFileError naming the term
  std::string name() const override { return "user:" + term_.name; }
  std::string meaning() const override { return "user term " + term_.expression; }
  std::vector<ParamSpec> shared_params() const override;
  double add(const SampleView& s, const double* p, double force_N) const override;
  std::string evidence(const EvidenceInput& in) const override;

 private:
  bool in_phase(Phase phase) const;
  UserTerm term_;
  std::vector<std::string> names_;
  mutable std::unique_ptr<mu::Parser> parser_;
  mutable double x_ = 0, t_ = 0, v_ = 0, p_ = 0, f_ = 0, l_ = 0, th_ = 0;
  mutable std::vector<double> values_;
};

}  // namespace rig::model::effects
