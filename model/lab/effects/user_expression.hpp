#pragma once
// A researcher's own term, written as an expression in the model file ([terms.NAME]) and
// evaluated with muParser. Variables: x [mm], t [s], v [mm/s], P [mmHg], F (the model's
// tissue force so far) [N], L (inserted length past the puncture) [mm], th (time in hold)
// [s], the phase indicators is_insertion, is_precut, is_cutting, is_hold, is_retraction
// (1 in that phase, else 0; the same phases as the term's `phase`), and any other name is a
// run covariate (numeric metadata or extra channel, e.g. blade_uses), which every run must
// have. Its parameters are fitted like any shared parameter. The term is added in its
// phase: insertion, precut, cutting (after the puncture), hold, retraction or all.
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
  // Not applicable when a run lacks one of the covariates the expression names.
  bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const override;
  double add(const SampleView& s, const double* p, double force_N) const override;
  std::string evidence(const EvidenceInput& in) const override;

  // The term with these fitted parameter values (in shared_params() order).
  UserTerm with_params(const double* p) const;
  const std::vector<std::string>& covariates() const { return covariate_names_; }
  // Whether a phase given by name is one of the term phases (insertion, precut, ...).
  static bool known_phase(const std::string& phase);
  static bool in_phase(const std::string& phase, Phase detected);

 private:
  static double* new_covariate(const char* name, void* self);
  void bind_run(const PreparedRun& run) const;  // throws std::invalid_argument naming the run

  UserTerm term_;
  std::vector<std::string> names_;
  std::unique_ptr<mu::Parser> parser_;
  mutable double x_ = 0, t_ = 0, v_ = 0, p_ = 0, f_ = 0, l_ = 0, th_ = 0;
  mutable double is_insertion_ = 0, is_precut_ = 0, is_cutting_ = 0, is_hold_ = 0,
                 is_retraction_ = 0;
  mutable std::vector<double> values_;
  // Covariates named by the expression: muParser holds pointers to the map's values (stable).
  mutable std::map<std::string, double> covariate_values_;
  std::vector<std::string> covariate_names_;
  mutable const RunData* bound_run_ = nullptr;
  mutable std::vector<const Channel*> covariate_channels_;  // per covariate, null for metadata
};

}  // namespace rig::model::effects
