#include "cut_summary.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rig::model {

CutSummary summarize_cut(const RunData& run, const ForceModel* model) {
  CutSummary out;
  out.samples = run.size();
  if (run.size() < 10) throw std::invalid_argument(run.source + ": too few samples for a summary");
  // The insertion ends at the deepest point.
  const auto deepest = std::max_element(run.x_mm.begin(), run.x_mm.end()) - run.x_mm.begin();
  out.max_depth_mm = run.x_mm[static_cast<std::size_t>(deepest)];
  const double iop = run.number("iop_mmHg").value_or(15.0);
  const double x_pf = model != nullptr ? model->final_depth_mm(iop) : out.max_depth_mm;
  double st = 0, sx = 0, stt = 0, stx = 0, n = 0, sq = 0, nq = 0;
  for (std::size_t i = 0; i <= static_cast<std::size_t>(deepest); ++i) {
    const double x = run.x_mm[i];
    if (x < 0.0) continue;
    if (x > 0.5 && x < out.max_depth_mm - 0.5) {
      st += run.t_s[i];
      sx += x;
      stt += run.t_s[i] * run.t_s[i];
      stx += run.t_s[i] * x;
      n += 1;
    }
    if (x < x_pf && run.force_N[i] > out.peak_force_N) {
      out.peak_force_N = run.force_N[i];
      out.x_at_peak_mm = x;
    }
    if (model != nullptr) {
      const double r = run.force_N[i] - model->baseline(x, iop);
      sq += r * r;
      nq += 1;
    }
  }
  if (n < 3) throw std::invalid_argument(run.source + ": no insertion deeper than 1 mm");
  out.velocity_mean_mm_s = (n * stx - st * sx) / (n * stt - st * st);
  out.commanded_velocity_mm_s = run.number("velocity_mm_s").value_or(out.velocity_mean_mm_s);
  out.velocity_error_pct = 100.0 * (out.velocity_mean_mm_s - out.commanded_velocity_mm_s) / out.commanded_velocity_mm_s;
  if (nq > 0) out.model_rmse_N = std::sqrt(sq / nq);
  return out;
}

}  // namespace rig::model
