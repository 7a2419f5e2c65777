#include "user_expression.hpp"

#include <set>
#include <sstream>

#include "effect_util.hpp"

namespace rig::model::effects {

UserExpression::UserExpression(const UserTerm& term) : term_(term), parser_(std::make_unique<mu::Parser>()) {
  for (const auto& [name, value] : term.params) {
    names_.push_back(name);
    values_.push_back(value);
  }
  const std::set<std::string> phases = {"insertion", "precut", "cutting", "hold", "retraction", "all"};
  if (phases.count(term.phase) == 0U) throw ModelFileError("terms." + term.name + ".phase: '" + term.phase + "' is not one of insertion, precut, cutting, hold, retraction, all");
  try {
    parser_->DefineVar("x", &x_);
    parser_->DefineVar("t", &t_);
    parser_->DefineVar("v", &v_);
    parser_->DefineVar("P", &p_);
    parser_->DefineVar("F", &f_);
    parser_->DefineVar("L", &l_);
    parser_->DefineVar("th", &th_);
    for (std::size_t k = 0; k < names_.size(); ++k) parser_->DefineVar(names_[k], &values_[k]);
    parser_->SetExpr(term.expression);
    parser_->Eval();  // reports unknown names and syntax errors now
  } catch (const mu::Parser::exception_type& e) {
    std::ostringstream what;
    what << "terms." << term.name << ".expression: " << e.GetMsg() << " at position " << e.GetPos() << " in '" << term.expression << "'";
    throw ModelFileError(what.str());
  }
}

std::vector<ParamSpec> UserExpression::shared_params() const {
  std::vector<ParamSpec> specs;
  for (std::size_t k = 0; k < names_.size(); ++k) {
    const double span = 10.0 * std::abs(values_[k]) + 1.0;
    specs.push_back({names_[k], "", values_[k], values_[k] - span, values_[k] + span});
  }
  return specs;
}

bool UserExpression::in_phase(Phase phase) const {
  const std::string& p = term_.phase;
  if (p == "all") return true;
  if (p == "insertion") return is_tissue_phase(phase) && phase != Phase::kHold;
  if (p == "precut") return phase == Phase::kPrecut;
  if (p == "cutting") return after_puncture(phase) && phase != Phase::kHold;
  if (p == "hold") return phase == Phase::kHold;
  return phase == Phase::kRetraction;
}

double UserExpression::add(const SampleView& s, const double* p, double force_N) const {
  if (!in_phase(s.phase)) return 0.0;
  x_ = s.x_mm;
  t_ = s.t_s;
  v_ = s.velocity_mm_s;
  p_ = s.run->iop_mmHg;
  f_ = force_N;
  l_ = s.inserted_mm;
  th_ = s.hold_s;
  for (std::size_t k = 0; k < values_.size(); ++k) values_[k] = p[k];
  const double value = parser_->Eval();
  return std::isfinite(value) ? value : 0.0;
}

std::string UserExpression::evidence(const EvidenceInput& in) const {
  std::string text = "user term " + term_.expression + " fitted with";
  for (std::size_t k = 0; k < names_.size(); ++k) text += " " + names_[k] + format(" = %.4g", in.shared[k]);
  return text;
}

}  // namespace rig::model::effects
