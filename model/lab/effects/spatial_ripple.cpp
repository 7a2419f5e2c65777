#include "spatial_ripple.hpp"

#include <algorithm>

#include "effect_util.hpp"

namespace rig::model::effects {

const std::vector<std::string>& SpatialRipple::form_names() {
  static const std::vector<std::string> kNames = {"3 harmonics", "sine", "growing with the load"};
  return kNames;
}

std::vector<ParamSpec> SpatialRipple::shared_params() const {
  std::vector<ParamSpec> out = {{"period", "mm", 1.0, 0.2, 5.0}};
  if (form_ == kSine) out.push_back({"harmonics", kFormLabelUnit, 1.0, 0.5, 1.5});
  if (form_ == kWithTheLoad) out.push_back({"with the load", kFormLabelUnit, 2.0, 1.5, 2.5});
  return out;
}

std::vector<std::vector<double>> SpatialRipple::starts() const {
  std::vector<std::vector<double>> out;
  for (double period = 0.25; period <= 4.0;
       period *= 1.01) {  // a ripple stays coherent over ~30 mm only within ~1 %
    if (form_ == kThreeHarmonics)
      out.push_back({period});
    else
      out.push_back({period, form_ == kSine ? 1.0 : 2.0});
  }
  return out;
}

// The force was tared where the run began (the carriage parked, its first samples): the
// ripple there was taken in by the tare, so each column is its value less its value at the
// start. No free offset: a constant per run is not a ripple (it is drift or tare).
void SpatialRipple::design(const SampleView& s, const double* p, double* row) const {
  if (form_ == kWithTheLoad) {  // no load where the force was tared: nothing to subtract [N]
    fourier(s.x_mm / p[0], 1, row);
    row[0] *= s.force_N, row[1] *= s.force_N;
    return;
  }
  // The value at the tare is the same for every sample of a run at one period: computed once
  // per (parked position, period, harmonics) on each fitting thread, not once per sample
  // (its sine and cosine were a tenth of a diagnosis' time, 2026-12-02). Exact: the same call.
  thread_local TareColumns tare;
  if (tare.parked_mm != s.run->parked_mm || tare.period_mm != p[0] ||
      tare.harmonics != harmonics()) {
    tare.parked_mm = s.run->parked_mm, tare.period_mm = p[0], tare.harmonics = harmonics();
    fourier(tare.parked_mm / tare.period_mm, tare.harmonics, tare.columns);
  }
  const double* at_tare = tare.columns;
  fourier(s.x_mm / p[0], harmonics(), row);
  for (int k = 0; k < 2 * harmonics(); ++k) row[k] -= at_tare[k];
}

std::string SpatialRipple::evidence(const EvidenceInput& in) const {
  if (form_ == kWithTheLoad) {
    std::vector<double> share =
        run_amplitudes(in.run_coefficients);  // per run: amplitude / force [1]
    return format(
               "ripple growing with the load: the residual is periodic in displacement with a %.3f "
               "mm period, its amplitude "
               "proportional to the force on the screw (%.1f %% of the force in the median run, "
               "phase differs by run)",
               in.shared[0], share.empty() ? 0.0 : 100.0 * median(std::move(share))) +
           honesty(in);
  }
  return std::string(form_ == kSine ? "sinusoidal ripple: " : "ripple with 3 harmonics: ") +
         format(
             "the residual is periodic in displacement with a %.3f mm period (amplitude up to %.4f "
             "N, phase differs by run)",
             in.shared[0], largest_amplitude(in.run_coefficients)) +
         honesty(in);
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
  why_not = format(
      "its best period, %.2f mm, repeats only %.1f times over the %.1f mm the runs traverse "
      "(median run; "
      "a ripple must be seen at least %.0f times): a smooth misfit of the baseline, not a ripple",
      period_mm, median_mm / period_mm, median_mm, kMinPeriodsSeen);
  return false;
}

}  // namespace rig::model::effects
