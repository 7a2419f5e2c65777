#include "feature_library.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>

#include "effects/user_expression.hpp"

namespace rig::model::explainer {
namespace {

// Functions of the sample alone. Products with the phase gates come on top.
const std::vector<std::string>& plain_bases() {
  static const std::vector<std::string> kBases = {
      "1",      "x",        "x^2",      "x^3",           // depth [mm]
      "L",      "L^2",                                   // inserted length past the puncture [mm]
      "v",      "abs(v)",   "sign(v)",  "ln(1+abs(v))",  // velocity [mm/s], direction
      "t",                                               // time since the run began [s]
      "F",      "F*x",      "F*abs(v)",                  // the model's tissue force [N]
      "(P-15)", "(P-15)*x", "(P-15)*F"};                 // IOP [mmHg] from the model's 15 mmHg
  return kBases;
}

// Functions of the time in hold: relaxation-like decays on a small grid of time constants.
const std::vector<std::string>& hold_bases() {
  static const std::vector<std::string> kBases = {"th", "exp(-th/0.3)", "exp(-th/1)", "exp(-th/3)",
                                                  "F*th"};
  return kBases;
}

std::string centred(const Covariate& c) {
  char text[64];
  std::snprintf(text, sizeof text, "%+.6g", -c.mean);
  return c.mean == 0.0 ? c.key : "(" + c.key + text + ")";
}

}  // namespace

const std::vector<std::string>& FeatureLibrary::gates() {
  // Narrow gates first: where two features coincide on the data, the explainer keeps the first.
  static const std::vector<std::string> kGates = {"precut",     "cutting",   "hold",
                                                  "retraction", "insertion", "all"};
  return kGates;
}

bool FeatureLibrary::usable_name(const std::string& key) {
  static const std::set<std::string> kTaken = {
      "x",         "t",          "v",       "P",
      "F",         "L",          "th",      "is_insertion",
      "is_precut", "is_cutting", "is_hold", "is_retraction",
      "_pi",       "_e"};
  if (key.empty() || kTaken.count(key) != 0U ||
      std::isdigit(static_cast<unsigned char>(key[0])) != 0)
    return false;
  for (const char c : key) {
    if (std::isalnum(static_cast<unsigned char>(c)) == 0 && c != '_') return false;
  }
  return true;
}

FeatureLibrary::FeatureLibrary(const std::vector<Covariate>& covariates, bool holds) {
  covariate_values_.assign(covariates.size(), 0.0);  // fixed size: muParser keeps pointers into it
  for (const Covariate& c : covariates) covariate_keys_.push_back(c.key);
  for (const std::string& e : plain_bases()) add_base(e, false);
  if (holds) {
    for (const std::string& e : hold_bases()) add_base(e, true);
  }
  for (const Covariate& c : covariates) {
    const std::string z = centred(c);
    for (const char* times : {"", "*x", "*F", "*L", "*abs(v)"}) add_base(z + times, false);
  }
  base_values_.assign(base_.size(), 0.0);
}

void FeatureLibrary::add_base(const std::string& expression, bool hold_only) {
  auto parser = std::make_unique<mu::Parser>();
  const std::pair<const char*, double*> variables[] = {
      {"x", &x_}, {"t", &t_}, {"v", &v_}, {"P", &p_}, {"F", &f_}, {"L", &l_}, {"th", &th_}};
  try {
    for (const auto& [name, address] : variables) parser->DefineVar(name, address);
    for (std::size_t k = 0; k < covariate_keys_.size(); ++k)
      parser->DefineVar(covariate_keys_[k], &covariate_values_[k]);
    parser->SetExpr(expression);
    parser->Eval();
  } catch (const mu::Parser::exception_type& e) {
    throw std::logic_error("explainer feature '" + expression + "': " + e.GetMsg());
  }
  const std::size_t index = base_.size();
  base_.push_back(std::move(parser));
  for (std::size_t g = 0; g < gates().size(); ++g) {
    if (hold_only && gates()[g] != "hold" && gates()[g] != "retraction") continue;
    features_.push_back({expression, gates()[g], index});
    gate_of_.push_back(g);
  }
}

void FeatureLibrary::row(const ProbedSample& s, const double* covariates, double* out) const {
  x_ = s.x_mm, t_ = s.t_s, v_ = s.velocity_mm_s, p_ = s.iop_mmHg, f_ = s.force_N,
  l_ = s.inserted_mm, th_ = s.hold_s;
  for (std::size_t k = 0; k < covariate_values_.size(); ++k) covariate_values_[k] = covariates[k];
  for (std::size_t b = 0; b < base_.size(); ++b) base_values_[b] = base_[b]->Eval();
  std::vector<bool> open(gates().size());
  for (std::size_t g = 0; g < gates().size(); ++g)
    open[g] = effects::UserExpression::in_phase(gates()[g], s.phase);
  for (std::size_t j = 0; j < features_.size(); ++j) {
    const double value = base_values_[features_[j].base];
    out[j] = open[gate_of_[j]] && std::isfinite(value) ? value : 0.0;
  }
}

}  // namespace rig::model::explainer
