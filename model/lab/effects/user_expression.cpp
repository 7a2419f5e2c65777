#include "user_expression.hpp"

#include <set>
#include <sstream>
#include <stdexcept>

#include "effect_util.hpp"

namespace rig::model::effects {
namespace {

const std::set<std::string>& variable_names() {
  static const std::set<std::string> kNames = {
      "x",         "t",          "v",       "P",
      "F",         "L",          "th",      "is_insertion",
      "is_precut", "is_cutting", "is_hold", "is_retraction"};
  return kNames;
}

}  // namespace

bool UserExpression::known_phase(const std::string& phase) {
  static const std::set<std::string> kPhases = {"insertion", "precut",     "cutting",
                                                "hold",      "retraction", "all"};
  return kPhases.count(phase) != 0U;
}

bool UserExpression::in_phase(const std::string& p, Phase phase) {
  if (p == "all") return true;
  if (p == "insertion") return is_tissue_phase(phase) && phase != Phase::kHold;
  if (p == "precut") return phase == Phase::kPrecut;
  if (p == "cutting") return after_puncture(phase) && phase != Phase::kHold;
  if (p == "hold") return phase == Phase::kHold;
  return p == "retraction" && phase == Phase::kRetraction;
}

double* UserExpression::new_covariate(const char* name, void* self) {
  auto* term = static_cast<UserExpression*>(self);
  term->covariate_names_.emplace_back(name);
  return &term->covariate_values_[name];
}

UserExpression::UserExpression(const UserTerm& term)
    : term_(term), parser_(std::make_unique<mu::Parser>()) {
  for (const auto& [name, value] : term.params) {
    if (variable_names().count(name) != 0U)
      throw ModelFileError("terms." + term.name + ".params." + name + ": '" + name +
                           "' is a variable of user terms, not a parameter name");
    names_.push_back(name);
    values_.push_back(value);
  }
  if (!known_phase(term.phase))
    throw ModelFileError("terms." + term.name + ".phase: '" + term.phase +
                         "' is not one of insertion, precut, cutting, hold, retraction, all");
  try {
    const std::pair<const char*, double*> variables[] = {{"x", &x_},
                                                         {"t", &t_},
                                                         {"v", &v_},
                                                         {"P", &p_},
                                                         {"F", &f_},
                                                         {"L", &l_},
                                                         {"th", &th_},
                                                         {"is_insertion", &is_insertion_},
                                                         {"is_precut", &is_precut_},
                                                         {"is_cutting", &is_cutting_},
                                                         {"is_hold", &is_hold_},
                                                         {"is_retraction", &is_retraction_}};
    for (const auto& [name, address] : variables) parser_->DefineVar(name, address);
    for (std::size_t k = 0; k < names_.size(); ++k) parser_->DefineVar(names_[k], &values_[k]);
    parser_->SetVarFactory(&UserExpression::new_covariate,
                           this);  // any other name: a run covariate
    parser_->SetExpr(term.expression);
    parser_->Eval();  // reports syntax errors now, and collects the covariates named
  } catch (const mu::Parser::exception_type& e) {
    std::ostringstream what;
    what << "terms." << term.name << ".expression: " << e.GetMsg() << " at position " << e.GetPos()
         << " in '" << term.expression << "'";
    throw ModelFileError(what.str());
  }
}

std::vector<ParamSpec> UserExpression::shared_params() const {
  std::vector<ParamSpec> specs;
  for (std::size_t k = 0; k < names_.size(); ++k) {
    const double span = 10.0 * std::abs(term_.params.at(names_[k])) + 1.0;
    const double initial = term_.params.at(names_[k]);
    specs.push_back({names_[k], "", initial, initial - span, initial + span});
  }
  return specs;
}

bool UserExpression::applicable(const std::vector<const PreparedRun*>& runs,
                                std::string& why_not) const {
  for (const PreparedRun* run : runs) {
    for (const std::string& key : covariate_names_) {
      if (!run->covariate(key, 0).has_value()) {
        why_not = "'" + key +
                  "' is not a variable (x, t, v, P, F, L, th, is_PHASE), a parameter, or a numeric "
                  "covariate of run " +
                  run->label();
        return false;
      }
    }
  }
  return true;
}

void UserExpression::bind_run(const PreparedRun& run) const {
  std::string why_not;
  if (!applicable({&run}, why_not)) throw std::invalid_argument(name() + ": " + why_not);
  covariate_channels_.clear();
  for (const std::string& key : covariate_names_) {
    const Channel* channel = run.data->channel(key);
    covariate_channels_.push_back(channel);
    if (channel == nullptr)
      covariate_values_[key] = *run.covariate(key, 0);  // metadata: constant over the run
  }
  bound_run_ = run.data;
}

double UserExpression::add(const SampleView& s, const double* p, double force_N) const {
  if (!in_phase(term_.phase, s.phase)) return 0.0;
  if (s.run->data != bound_run_) bind_run(*s.run);
  for (std::size_t k = 0; k < covariate_names_.size(); ++k) {
    if (covariate_channels_[k] != nullptr)
      covariate_values_[covariate_names_[k]] = covariate_channels_[k]->values[s.i];
  }
  x_ = s.x_mm;
  t_ = s.t_s;
  v_ = s.velocity_mm_s;
  p_ = s.run->iop_mmHg;
  f_ = force_N;
  l_ = s.inserted_mm;
  th_ = s.hold_s;
  is_insertion_ = in_phase("insertion", s.phase) ? 1.0 : 0.0;
  is_precut_ = s.phase == Phase::kPrecut ? 1.0 : 0.0;
  is_cutting_ = in_phase("cutting", s.phase) ? 1.0 : 0.0;
  is_hold_ = s.phase == Phase::kHold ? 1.0 : 0.0;
  is_retraction_ = s.phase == Phase::kRetraction ? 1.0 : 0.0;
  for (std::size_t k = 0; k < values_.size(); ++k) values_[k] = p[k];
  const double value = parser_->Eval();
  return std::isfinite(value) ? value : 0.0;
}

UserTerm UserExpression::with_params(const double* p) const {
  UserTerm out = term_;
  for (std::size_t k = 0; k < names_.size(); ++k) out.params[names_[k]] = p[k];
  return out;
}

std::string UserExpression::evidence(const EvidenceInput& in) const {
  std::string text = "user term " + term_.expression + " fitted with";
  for (std::size_t k = 0; k < names_.size(); ++k)
    text += " " + names_[k] + format(" = %.4g", in.shared[k]);
  return text;
}

}  // namespace rig::model::effects
