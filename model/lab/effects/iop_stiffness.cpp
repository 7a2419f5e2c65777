#include "iop_stiffness.hpp"

#include <algorithm>

#include "effect_util.hpp"

namespace rig::model::effects {

const std::vector<std::string>& IopStiffness::form_names() {
  static const std::vector<std::string> kNames = {"exponential", "exponential-quadratic", "linear",
                                                  "saturating", "shorter toe"};
  return kNames;
}

std::vector<ParamSpec> IopStiffness::shared_params() const {
  switch (form_) {
    case kExponential:
      return {{"k", "1/mmHg", 0.0, -0.5, 0.5}};
    case kLinear:
      return {{"k_lin", "1/mmHg", 0.0, -0.2, 2.0}};
    case kSaturating:
      return {{"A", "1", 0.0, -0.9, 5.0}, {"P0", "mmHg", 3.0, 0.3, 50.0}};
    case kShorterToe:
      return {{"s", "mm/mmHg", 0.0, -0.3, 0.3}};
    default:
      return {{"k1", "1/mmHg", 0.0, -0.5, 0.5}, {"k2", "1/mmHg^2", 0.0, -0.2, 0.2}};
  }
}

std::vector<std::vector<double>> IopStiffness::starts() const {
  if (form_ != kSaturating) return EffectTerm::starts();
  std::vector<std::vector<double>> out;  // A = 0 leaves P0 without a gradient
  for (const double p0 : {1.0, 3.0, 10.0}) out.push_back({0.3, p0}), out.push_back({-0.2, p0});
  return out;
}

bool IopStiffness::applicable(const std::vector<const PreparedRun*>& runs,
                              std::string& why_not) const {
  double lo = 1e9, hi = -1e9;
  for (const PreparedRun* r : runs) {
    if (!r->iop_known) continue;
    lo = std::min(lo, r->iop_mmHg);
    hi = std::max(hi, r->iop_mmHg);
  }
  if (hi - lo < 0.9) why_not = "runs do not span at least 1 mmHg of IOP";
  return hi - lo >= 0.9;
}

double IopStiffness::factor(double dp, const double* p) const {
  switch (form_) {
    case kExponential:
      return std::exp(p[0] * dp);
    case kLinear:
      return std::max(0.05, 1.0 + p[0] * dp);
    case kSaturating:
      return std::max(0.05, 1.0 + p[0] * std::tanh(dp / p[1]));
    case kShorterToe:
      return 1.0;  // stiffness unchanged: the toe moves (toe_end_mm)
    default:
      return std::exp(p[0] * dp + p[1] * dp * dp);
  }
}

void IopStiffness::adjust_model(const PreparedRun& run, const double* p,
                                ContinuousParams& model) const {
  if (!run.iop_known) return;
  const double f = factor(run.iop_mmHg - 15.0, p);
  model.a *= f;
  model.b *= f;
  model.x1 = toe_end_mm(run.iop_mmHg - 15.0, p, model.x1);
}

double IopStiffness::toe_end_mm(double dp, const double* p, double x1_mm) const {
  return form_ == kShorterToe ? std::max(0.0, x1_mm - p[0] * dp) : x1_mm;
}

// Read at each run's IOP: the stiffness laws scale both tissue scales; the shorter toe
// changes the pre-cut force alone.
EyeDof IopStiffness::eye_level_params(const double* /*p*/) const {
  const int k = static_cast<int>(shared_params().size());
  return form_ == kShorterToe ? EyeDof{k, 0, 0} : EyeDof{k, k, 0};
}

std::string IopStiffness::evidence(const EvidenceInput& in) const {
  double lo = 1e9, hi = -1e9;
  for (const PreparedRun* r : in.runs)
    lo = std::min(lo, r->iop_mmHg), hi = std::max(hi, r->iop_mmHg);
  const double* p = in.shared;
  std::string law;
  switch (form_) {
    case kExponential:
      law = format("exponential in IOP, %+.1f %% per mmHg: ", 100.0 * p[0]);
      break;
    case kLinear:
      law = format("linear in IOP, %+.1f %% of the 15 mmHg stiffness per mmHg: ", 100.0 * p[0]);
      break;
    case kSaturating:
      law =
          format("saturating in IOP, at most %+.0f %%, half-way by about %.1f mmHg: ", 100.0 * p[0],
                 0.55 * p[1]);
      break;
    case kShorterToe:
      return format(
                 "pre-stressed by the pressure: the toe region ends %+.3f mm earlier per mmHg, "
                 "%+.2f mm at %.0f mmHg against %.0f mmHg "
                 "(slopes unchanged)",
                 p[0], p[0] * (hi - lo), hi, lo) +
             honesty(in);
    default:
      law = format("exponential-quadratic in IOP, %+.1f %% per mmHg, curvature %+.3f /mmHg^2: ",
                   100.0 * p[0], p[1]);
      break;
  }
  return law +
         format(
             "pre-cut stiffness is %+.1f %% at %.0f mmHg and %+.1f %% at %.0f mmHg against 15 mmHg",
             100.0 * (factor(lo - 15.0, p) - 1.0), lo, 100.0 * (factor(hi - 15.0, p) - 1.0), hi) +
         honesty(in);
}

}  // namespace rig::model::effects
