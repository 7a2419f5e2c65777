#include "covariate_scaling.hpp"

#include "effect_util.hpp"

namespace rig::model::effects {

const std::vector<std::string>& CovariateScaling::form_names() {
  static const std::vector<std::string> kNames = {
      "per phase, quadratic",    "exponential, all phases",  "linear, all phases",
      "after the puncture only", "before the puncture only", "moves the puncture"};
  return kNames;
}

std::vector<ParamSpec> CovariateScaling::shared_params() const {
  switch (form_) {
    case kExponential:
      return {{"c", "1", 0.0, -2.0, 2.0}};
    case kLinear:
      return {{"c_lin", "1", 0.0, -0.9, 0.9}};
    case kAfterPuncture:
      return {{"c_cut", "1", 0.0, -2.0, 2.0}};
    case kBeforePuncture:
      return {{"c_pre", "1", 0.0, -2.0, 2.0}};
    case kPunctureShift:
      return {{"xpi_1", "mm", 0.0, -3.0, 3.0}, {"xpi_2", "mm", 0.0, -1.5, 1.5}};
    default:
      return {{"c1", "1", 0.0, -2.0, 2.0},
              {"c2", "1", 0.0, -1.0, 1.0},
              {"c3", "1", 0.0, -2.0, 2.0},
              {"c4", "1", 0.0, -1.0, 1.0}};
  }
}

// A puncture that moves by millimetres is a different minimum from one that stays: the
// fitter starts from several slopes [mm per spread] and keeps the best (model_family.cpp).
std::vector<std::vector<double>> CovariateScaling::starts() const {
  if (form_ != kPunctureShift) return EffectTerm::starts();
  std::vector<std::vector<double>> out;
  for (const double slope_mm : {-2.0, -1.0, -0.4, 0.0, 0.4, 1.0, 2.0})
    out.push_back({slope_mm, 0.0});
  return out;
}

bool CovariateScaling::applicable(const std::vector<const PreparedRun*>& runs,
                                  std::string& why_not) const {
  for (const PreparedRun* r : runs) {
    if (!r->covariate(key_, 0)) {
      why_not = "'" + key_ + "' missing in " + r->label();
      return false;
    }
  }
  if (range_.spread <= 0.0) why_not = "'" + key_ + "' does not vary";
  return range_.spread > 0.0;
}

// Softer or stiffer tissue yields earlier or later: the puncture depth moves by
// xpi_1 z + xpi_2 z^2 [mm], the forces themselves unscaled.
void CovariateScaling::adjust_model(const PreparedRun& run, const double* p,
                                    ContinuousParams& model) const {
  if (form_ != kPunctureShift) return;
  const double z = z_of(run.covariate(key_, 0).value_or(range_.mean));
  model.x_pi_shift += p[0] * z + p[1] * z * z;
}

// The puncture form's slope and curvature are the coefficients of z and z^2 [mm per spread,
// per spread squared]: a law the lab can place from the eyes' own shifts (puncture_law.hpp).
std::vector<std::size_t> CovariateScaling::puncture_regressors(const PreparedRun& run,
                                                               std::vector<double>& values) const {
  values.clear();
  if (form_ != kPunctureShift) return {};
  const double z = z_of(run.covariate(key_, 0).value_or(range_.mean));
  values = {z, z * z};
  return {0, 1};
}

double CovariateScaling::scale(const SampleView& s, const double* p) const {
  if (form_ == kPunctureShift) return 1.0;
  const double z = z_of(s.run->covariate(key_, s.i).value_or(range_.mean));
  switch (form_) {
    case kExponential:
      return std::exp(p[0] * z);
    case kLinear:
      return std::max(0.05, 1.0 + p[0] * z);
    case kAfterPuncture:
      return s.after_puncture ? std::exp(p[0] * z) : 1.0;
    case kBeforePuncture:
      return s.after_puncture ? 1.0 : std::exp(p[0] * z);
    default:
      return s.after_puncture ? std::exp(p[2] * z + p[3] * z * z)
                              : std::exp(p[0] * z + p[1] * z * z);
  }
}

// Each slope or curvature is fitted on one value per eye, where it acts.
EyeDof CovariateScaling::eye_level_params(const double* /*p*/) const {
  switch (form_) {
    case kExponential:
    case kLinear:
      return {1, 1, 0};
    case kAfterPuncture:
      return {0, 1, 0};
    case kBeforePuncture:
      return {1, 0, 0};
    case kPunctureShift:
      return {0, 0, 2};
    default:
      return {2, 2, 0};
  }
}

std::string CovariateScaling::evidence(const EvidenceInput& in) const {
  const double* p = in.shared;
  const double per_unit = 100.0 * p[0] / range_.spread;  // the slope at the mean [% per unit]
  std::string span = format(" (runs span %.3g +- %.3g", range_.mean, range_.spread);
  if (std::isfinite(range_.low) && std::isfinite(range_.high))
    span += format("; held to %.3g..%.3g, the values fitted on, and %.3g past them", range_.low,
                   range_.high, range_.reach);
  span += ")";
  std::string text;
  switch (form_) {
    case kExponential:
      text = format(
                 "exponential in the covariate, all phases: tissue force changes %+.1f %% per unit "
                 "of ",
                 per_unit) +
             key_;
      break;
    case kLinear:
      text =
          format("linear in the covariate, all phases: tissue force changes %+.1f %% per unit of ",
                 per_unit) +
          key_;
      break;
    case kAfterPuncture:
      text = format("acts after the puncture only: cutting force changes %+.1f %% per unit of ",
                    per_unit) +
             key_;
      break;
    case kBeforePuncture:
      text = format("acts before the puncture only: pre-cut force changes %+.1f %% per unit of ",
                    per_unit) +
             key_;
      break;
    case kPunctureShift:
      text = format("moves the puncture: %+.3f mm per unit of ", p[0] / range_.spread) + key_ +
             format(" at the mean (curvature %+.3f mm per spread squared)", p[1]);
      break;
    default:
      text = format("per phase: tissue force changes %+.1f %% per unit of ", per_unit) + key_ +
             format(" before the puncture and %+.1f %% per unit after it",
                    100.0 * p[2] / range_.spread);
  }
  return text + span + honesty(in);
}

}  // namespace rig::model::effects
