#include "cut_summary.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "phases.hpp"

namespace rig::model {

namespace {

// The velocity the rig held while it moved [mm/s]: the median of the slopes over 0.2 s spans
// of the insertion (x between 0.5 mm and 0.5 mm short of the deepest point). A stall of the
// whole machine (rigd and the simulated DAQ off the CPU together: the simulated world stops,
// rigd's clock does not) is a gap in the record, not a slow cut; a least-squares slope over
// the whole insertion counted an 80 ms stall as 1.25 % slow. std::nullopt if no span fits.
constexpr double kSpan_s = 0.2;
constexpr double kEdge_mm = 0.5;  // the start and the end of the insertion are left out

bool steady(double x_mm, double max_depth_mm) {
  return x_mm > kEdge_mm && x_mm < max_depth_mm - kEdge_mm;
}

std::optional<double> median_held_velocity(const RunData& run, std::size_t deepest,
                                           double max_depth_mm) {
  std::vector<double> slopes;
  std::size_t j = 0;
  for (std::size_t i = 0; i <= deepest; ++i) {
    if (!steady(run.x_mm[i], max_depth_mm)) continue;
    j = std::max(j, i + 1);
    while (j <= deepest && run.t_s[j] < run.t_s[i] + kSpan_s) ++j;
    if (j > deepest || run.x_mm[j] >= max_depth_mm - kEdge_mm) continue;
    slopes.push_back((run.x_mm[j] - run.x_mm[i]) / (run.t_s[j] - run.t_s[i]));
  }
  if (slopes.empty()) return std::nullopt;
  return median(std::move(slopes));
}

}  // namespace

CutSummary summarize_cut(const RunData& run, const ForceModel* model) {
  CutSummary out;
  out.samples = run.size();
  if (run.size() < 10) throw std::invalid_argument(run.source + ": too few samples for a summary");
  // The insertion ends at the deepest point.
  const auto deepest = std::max_element(run.x_mm.begin(), run.x_mm.end()) - run.x_mm.begin();
  out.max_depth_mm = run.x_mm[static_cast<std::size_t>(deepest)];
  const double iop = run.number("iop_mmHg").value_or(15.0);
  const double x_pf = model != nullptr ? model->final_depth_mm(iop) : out.max_depth_mm;
  double sq = 0, nq = 0;
  for (std::size_t i = 0; i <= static_cast<std::size_t>(deepest); ++i) {
    const double x = run.x_mm[i];
    if (i > 0 && steady(x, out.max_depth_mm)) {
      out.longest_gap_ms = std::max(out.longest_gap_ms, 1e3 * (run.t_s[i] - run.t_s[i - 1]));
    }
    if (x < 0.0) continue;
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
  const std::optional<double> held =
      median_held_velocity(run, static_cast<std::size_t>(deepest), out.max_depth_mm);
  if (!held)
    throw std::invalid_argument(run.source + ": no insertion deeper than 1 mm that lasts 0.2 s");
  out.velocity_mm_s = *held;
  out.commanded_velocity_mm_s = run.number("velocity_mm_s").value_or(out.velocity_mm_s);
  out.velocity_error_pct =
      100.0 * (out.velocity_mm_s - out.commanded_velocity_mm_s) / out.commanded_velocity_mm_s;
  if (nq > 0) out.model_rmse_N = std::sqrt(sq / nq);
  return out;
}

}  // namespace rig::model
