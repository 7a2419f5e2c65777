#include "force_model.hpp"

#include <algorithm>
#include <cmath>

namespace rig::model {

double IopTable::interpolate(const std::vector<double>& values, double iop,
                             bool* extrapolated) const {
  const std::size_t n = iop_mmHg.size();
  if (extrapolated != nullptr) *extrapolated = iop < iop_mmHg.front() || iop > iop_mmHg.back();
  if (n == 1) return values.front();
  std::size_t i = 1;
  while (i < n - 1 && iop > iop_mmHg[i]) ++i;
  const double slope = (values[i] - values[i - 1]) / (iop_mmHg[i] - iop_mmHg[i - 1]);
  return values[i - 1] + slope * (iop - iop_mmHg[i - 1]);
}

double PrintedParams::value(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return i < values.size() ? values[i] : 0.0;
  }
  return 0.0;
}

bool PrintedParams::has(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return i < values.size();
  }
  return false;
}

ForceModel ForceModel::paper_interpreted() {
  return ForceModel{};
}

double ForceModel::puncture_depth_mm(double iop) const {
  return table.interpolate(table.x_pi_mm, iop) +
         (form == ModelForm::kContinuous ? params.x_pi_shift : 0.0);
}

double ForceModel::final_depth_mm(double iop) const {
  return table.interpolate(table.x_pf_mm, iop) +
         (form == ModelForm::kContinuous ? params.x_pf_shift : 0.0);
}

bool ForceModel::extrapolates(double iop) const {
  bool out = false;
  table.interpolate(table.x_pi_mm, iop, &out);
  return out;
}

ForceModel::RunDepths ForceModel::depths(double iop_mmHg) const {
  return {iop_mmHg, puncture_depth_mm(iop_mmHg), final_depth_mm(iop_mmHg)};
}

double ForceModel::baseline(double x_mm, double iop_mmHg) const {
  if (x_mm <= 0.0) return 0.0;
  return form == ModelForm::kPrinted ? as_printed(x_mm, iop_mmHg)
                                     : continuous(x_mm, depths(iop_mmHg));
}

double ForceModel::baseline(double x_mm, double front_mm, double iop_mmHg) const {
  return form == ModelForm::kPrinted ? baseline(x_mm, iop_mmHg)
                                     : baseline(x_mm, front_mm, depths(iop_mmHg));
}

double ForceModel::baseline(double x_mm, double front_mm, const RunDepths& run) const {
  if (form == ModelForm::kPrinted) return baseline(x_mm, run.iop_mmHg);
  const double at = std::max(x_mm, front_mm);  // held or withdrawn: the force reached at the front
  if (at <= 0.0) return 0.0;
  const double force = continuous(at, run);
  if (x_mm >= front_mm) return force;
  return force * std::max(0.0, 1.0 - (front_mm - x_mm) / std::max(params.w_release, 1e-4));
}

double cutting_plateau(const ContinuousParams& p, double x_mm, double iop_mmHg) {
  const double arg = std::max(x_mm - p.e, 1e-3);
  return p.d * (std::log(arg) - p.f * x_mm) + p.g * iop_mmHg + p.g0;
}

double ForceModel::continuous(double x, const RunDepths& run) const {
  const ContinuousParams& p = params;
  const double iop = run.iop_mmHg;
  const double xpi = run.x_pi_mm;
  const double xpf = run.x_pf_mm;
  const double xc = std::min(p.x_c, xpf - 1e-3);
  auto precut = [&](double at) { return at <= p.x1 ? p.a * at : p.a * p.x1 + p.b * (at - p.x1); };
  if (x < xpi) return precut(x);
  const double w = std::max(p.w_drop, 1e-4);
  if (x < xpi + w) {
    const double peak = precut(xpi);
    const double end = cutting_plateau(p, xpi + w, iop);
    return peak + (end - peak) * (x - xpi) / w;
  }
  if (x < xc) return cutting_plateau(p, x, iop);
  if (x < xpf) return cutting_plateau(p, xc, iop) * (xpf - x) / (xpf - xc);
  return 0.0;
}

double ForceModel::as_printed(double x, double iop) const {
  const PrintedParams& p = printed;
  auto v = [&](const char* key) { return p.value(key); };
  const double xpi = puncture_depth_mm(iop);
  const double xpf = final_depth_mm(iop);
  if (x <= p.x_toe_end_mm) return v("a") * x;
  if (x <= xpi) return v("b") * x - v("c");
  if (x <= p.x_cut_end_mm)
    return v("d") * (std::log(std::max(x - v("e"), 1e-12)) - v("f") * x) + v("g") * iop;
  if (x <= xpf) return v("h") * x + v("m") + v("n") * iop;
  return 0.0;
}

}  // namespace rig::model
