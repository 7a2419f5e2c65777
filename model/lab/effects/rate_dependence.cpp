#include "rate_dependence.hpp"

#include <algorithm>

#include "effect_util.hpp"

namespace rig::model::effects {

const std::vector<std::string>& RateDependence::form_names() {
  static const std::vector<std::string> kNames = {"power law", "log-quadratic", "linear",
                                                  "saturating"};
  return kNames;
}

std::vector<ParamSpec> RateDependence::shared_params() const {
  std::vector<ParamSpec> out = law_params();
  out.push_back({"at_rest", "1", 1.0, 0.0, 1.5});
  out.push_back({"before_puncture", "1", 1.0, 0.0, 1.5});
  return out;
}

int RateDependence::law_param_count() const {
  return form_ == kPowerLaw || form_ == kLinear ? 1 : 2;
}

std::vector<ParamSpec> RateDependence::law_params() const {
  switch (form_) {
    case kPowerLaw:
      return {{"n", "1", 0.0, -2.0, 2.0}};
    case kLinear:
      return {{"c", "s/mm", 0.0, -0.45, 2.0}};
    case kSaturating:
      return {{"A", "1", 0.0, -0.9, 20.0}, {"v_c", "mm/s", 1.0, 0.05, 50.0}};
    default:
      return {{"b1", "1 per ln(v)", 0.0, -2.0, 2.0}, {"b2", "1 per ln(v)^2", 0.0, -2.0, 2.0}};
  }
}

std::vector<std::vector<double>> RateDependence::starts() const {
  std::vector<std::vector<double>> laws;
  if (form_ == kSaturating) {  // A = 0 leaves v_c without a gradient
    for (const double v_c : {0.3, 1.0, 3.0, 10.0})
      laws.push_back({0.5, v_c}), laws.push_back({-0.3, v_c});
  } else {
    std::vector<double> law;
    for (const ParamSpec& spec : law_params()) law.push_back(spec.initial);
    laws.push_back(law);
  }
  std::vector<std::vector<double>> out;  // where it acts: everywhere, while cutting only
  for (const auto& [rest, pre] : {std::pair{1.0, 1.0}, std::pair{0.0, 1.0}, std::pair{0.0, 0.0}}) {
    for (auto start : laws) {
      start.push_back(rest);
      start.push_back(pre);
      out.push_back(std::move(start));
    }
  }
  return out;
}

bool RateDependence::applicable(const std::vector<const PreparedRun*>& runs,
                                std::string& why_not) const {
  double lo = 1e9, hi = 0.0;
  for (const PreparedRun* r : runs)
    lo = std::min(lo, r->velocity_cmd_mm_s), hi = std::max(hi, r->velocity_cmd_mm_s);
  if (hi < lo * 1.2) why_not = "all runs at about the same velocity";
  return hi >= lo * 1.2;
}

double RateDependence::factor(double velocity_mm_s, const double* p) const {
  const double v = std::max(velocity_mm_s, 0.01);
  switch (form_) {
    case kPowerLaw:
      return std::pow(v / v_ref_, p[0]);
    case kLinear:
      return std::max(0.05, 1.0 + p[0] * (v - v_ref_));
    case kSaturating:
      return (1.0 + p[0] * v / (v + p[1])) / std::max(1.0 + p[0] * v_ref_ / (v_ref_ + p[1]), 0.05);
    default: {
      const double u = std::log(v / v_ref_);
      return std::exp(p[0] * u + p[1] * u * u);
    }
  }
}

// The run's law at its insertion velocity, while the blade advances; a fitted share of it
// where the blade stands (stops, the hold) or withdraws, and before the puncture: a
// viscous cutting resistance needs motion and a cut, an elastic stiffening does not.
double RateDependence::scale(const SampleView& s, const double* p) const {
  const double f = factor(s.run->velocity_cmd_mm_s, p);
  const int k = law_param_count();
  const bool standing = s.phase == Phase::kHold || s.phase == Phase::kRetraction || s.hold_s > 0.0;
  double share = standing ? p[k] : 1.0;
  if (!s.after_puncture) share *= p[k + 1];
  return std::max(0.05, 1.0 + share * (f - 1.0));
}

// The law is read at each run's insertion velocity: one value per eye. It acts on the
// cutting scale, and on the pre-cut one where a share of it acts before the puncture.
EyeDof RateDependence::eye_level_params(const double* p) const {
  const int k = law_param_count();
  constexpr double kActsBeforePuncture = 0.1;  // share of the law [1]
  return {p[k + 1] >= kActsBeforePuncture ? k : 0, k, 0};
}

std::string RateDependence::evidence(const EvidenceInput& in) const {
  double lo = 1e9, hi = 0.0;
  for (const PreparedRun* r : in.runs)
    lo = std::min(lo, r->velocity_cmd_mm_s), hi = std::max(hi, r->velocity_cmd_mm_s);
  const double* p = in.shared;
  std::string law;
  switch (form_) {
    case kPowerLaw:
      law = format("power-law rate, exponent %.2f: ", p[0]);
      break;
    case kLinear:
      law = format("linear rate, %+.1f %% per mm/s: ", 100.0 * p[0]);
      break;
    case kSaturating:
      law = format("saturating rate (Carreau-like), %+.0f %% at most, half-way at %.2f mm/s: ",
                   100.0 * p[0], p[1]);
      break;
    default:
      law = format("log-quadratic rate, %.2f ln(v) %+.2f ln(v)^2: ", p[0], p[1]);
      break;
  }
  const int k = law_param_count();
  return law +
         format(
             "tissue force is %+.1f %% at %.2g mm/s and %+.1f %% at %.2g mm/s relative to the "
             "model's velocity",
             100.0 * (factor(lo, p) - 1.0), lo, 100.0 * (factor(hi, p) - 1.0), hi) +
         format(
             "; %.0f %% of it remains where the blade stands or withdraws, %.0f %% acts before the "
             "puncture",
             100.0 * p[k], 100.0 * p[k + 1]) +
         honesty(in);
}

}  // namespace rig::model::effects
