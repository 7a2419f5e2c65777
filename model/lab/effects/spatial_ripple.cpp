#include "spatial_ripple.hpp"

#include <algorithm>

#include "effect_util.hpp"

namespace rig::model::effects {

const std::vector<std::string>& SpatialRipple::form_names() {
  static const std::vector<std::string> kNames = {"3 harmonics", "sine"};
  return kNames;
}

std::vector<ParamSpec> SpatialRipple::shared_params() const {
  std::vector<ParamSpec> out = {{"period", "mm", 1.0, 0.2, 5.0}};
  if (form_ == kSine) out.push_back({"harmonics", kFormLabelUnit, 1.0, 0.5, 1.5});
  return out;
}

std::vector<std::vector<double>> SpatialRipple::starts() const {
  std::vector<std::vector<double>> out;
  for (double period = 0.25; period <= 4.0; period *= 1.01) {  // a ripple stays coherent over ~30 mm only within ~1 %
    out.push_back(form_ == kSine ? std::vector<double>{period, 1.0} : std::vector<double>{period});
  }
  return out;
}

// The force was tared where the run began (the carriage parked, its first samples): the
// ripple there was taken in by the tare, so each column is its value less its value at the
// start. No free offset: a constant per run is not a ripple (it is drift or tare).
void SpatialRipple::design(const SampleView& s, const double* p, double* row) const {
  double at_tare[6];
  fourier(s.run->parked_mm / p[0], harmonics(), at_tare);
  fourier(s.x_mm / p[0], harmonics(), row);
  for (int k = 0; k < 2 * harmonics(); ++k) row[k] -= at_tare[k];
}

std::string SpatialRipple::evidence(const EvidenceInput& in) const {
  return std::string(form_ == kSine ? "sinusoidal ripple: " : "ripple with 3 harmonics: ") +
         format("the residual is periodic in displacement with a %.3f mm period (amplitude up to %.4f N, phase differs by run)",
                in.shared[0], largest_amplitude(in.run_coefficients)) + honesty(in);
}

bool SpatialRipple::identifiable(const EvidenceInput& fitted, std::string& why_not) const {
  std::vector<double> traversed_mm;  // per run: the depth range of its analysed samples
  for (const PreparedRun* run : fitted.runs) {
    if (run->analysed.empty()) continue;
    double lo = run->data->x_mm[run->analysed.front()];
    double hi = lo;
    for (const std::size_t i : run->analysed) {
      lo = std::min(lo, run->data->x_mm[i]);
      hi = std::max(hi, run->data->x_mm[i]);
    }
    traversed_mm.push_back(hi - lo);
  }
  if (traversed_mm.empty()) return true;
  const double median_mm = median(std::move(traversed_mm));
  const double period_mm = fitted.shared[0];
  if (median_mm >= kMinPeriodsSeen * period_mm) return true;
  why_not = format("its best period, %.2f mm, repeats only %.1f times over the %.1f mm the runs traverse (median run; "
                   "a ripple must be seen at least %.0f times): a smooth misfit of the baseline, not a ripple",
                   period_mm, median_mm / period_mm, median_mm, kMinPeriodsSeen);
  return false;
}

}  // namespace rig::model::effects
