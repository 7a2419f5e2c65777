#include "effect_term.hpp"

namespace rig::model {

bool EffectTerm::applicable(const std::vector<const PreparedRun*>& /*runs*/,
                            std::string& /*why_not*/) const {
  return true;
}
void EffectTerm::adjust_model(const PreparedRun& /*run*/, const double* /*p*/,
                              ContinuousParams& /*model*/) const {}
double EffectTerm::x_shift(const SampleView& /*s*/, const double* /*p*/) const {
  return 0.0;
}
double EffectTerm::scale(const SampleView& /*s*/, const double* /*p*/) const {
  return 1.0;
}
double EffectTerm::add(const SampleView& /*s*/, const double* /*p*/, double /*force_N*/) const {
  return 0.0;
}
std::vector<std::vector<double>> EffectTerm::starts() const {
  std::vector<double> initial;
  for (const ParamSpec& s : shared_params()) initial.push_back(s.initial);
  return {initial};
}

void EffectTerm::design(const SampleView& /*s*/, const double* /*p*/, double* /*row*/) const {}

}  // namespace rig::model
