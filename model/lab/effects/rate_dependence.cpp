#include "rate_dependence.hpp"

#include <algorithm>

#include "effect_util.hpp"

namespace rig::model::effects {

const std::vector<std::string>& RateDependence::form_names() {
  static const std::vector<std::string> kNames = {"power law", "log-quadratic", "linear", "saturating"};
  return kNames;
}

std::vector<ParamSpec> RateDependence::shared_params() const {
  switch (form_) {
    case kPowerLaw: return {{"n", "1", 0.0, -2.0, 2.0}};
    case kLinear: return {{"c", "s/mm", 0.0, -0.45, 2.0}};
    case kSaturating: return {{"A", "1", 0.0, -0.9, 20.0}, {"v_c", "mm/s", 1.0, 0.05, 50.0}};
    default: return {{"b1", "1 per ln(v)", 0.0, -2.0, 2.0}, {"b2", "1 per ln(v)^2", 0.0, -2.0, 2.0}};
  }
}

std::vector<std::vector<double>> RateDependence::starts() const {
  if (form_ != kSaturating) return EffectTerm::starts();
  std::vector<std::vector<double>> out;  // A = 0 leaves v_c without a gradient
  for (const double v_c : {0.3, 1.0, 3.0, 10.0}) out.push_back({0.5, v_c}), out.push_back({-0.3, v_c});
  return out;
}

bool RateDependence::applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const {
  double lo = 1e9, hi = 0.0;
  for (const PreparedRun* r : runs) lo = std::min(lo, r->velocity_cmd_mm_s), hi = std::max(hi, r->velocity_cmd_mm_s);
  if (hi < lo * 1.2) why_not = "all runs at about the same velocity";
  return hi >= lo * 1.2;
}

double RateDependence::factor(double velocity_mm_s, const double* p) const {
  const double v = std::max(velocity_mm_s, 0.01);
  switch (form_) {
    case kPowerLaw: return std::pow(v / v_ref_, p[0]);
    case kLinear: return std::max(0.05, 1.0 + p[0] * (v - v_ref_));
    case kSaturating: return (1.0 + p[0] * v / (v + p[1])) / std::max(1.0 + p[0] * v_ref_ / (v_ref_ + p[1]), 0.05);
    default: {
      const double u = std::log(v / v_ref_);
      return std::exp(p[0] * u + p[1] * u * u);
    }
  }
}

double RateDependence::scale(const SampleView& s, const double* p) const { return factor(s.run->velocity_cmd_mm_s, p); }

std::string RateDependence::evidence(const EvidenceInput& in) const {
  double lo = 1e9, hi = 0.0;
  for (const PreparedRun* r : in.runs) lo = std::min(lo, r->velocity_cmd_mm_s), hi = std::max(hi, r->velocity_cmd_mm_s);
  const double* p = in.shared;
  std::string law;
  switch (form_) {
    case kPowerLaw: law = format("power-law rate, exponent %.2f: ", p[0]); break;
    case kLinear: law = format("linear rate, %+.1f %% per mm/s: ", 100.0 * p[0]); break;
    case kSaturating: law = format("saturating rate (Carreau-like), %+.0f %% at most, half-way at %.2f mm/s: ", 100.0 * p[0], p[1]); break;
    default: law = format("log-quadratic rate, %.2f ln(v) %+.2f ln(v)^2: ", p[0], p[1]); break;
  }
  return law + format("tissue force is %+.1f %% at %.2g mm/s and %+.1f %% at %.2g mm/s relative to the model's velocity",
                      100.0 * (factor(lo, p) - 1.0), lo, 100.0 * (factor(hi, p) - 1.0), hi) + honesty(in);
}

}  // namespace rig::model::effects
