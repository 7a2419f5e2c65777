#include "recorded_run_source.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rig::haptic {

RecordedRunSource::RecordedRunSource(const model::RunData& run) {
  const auto deepest = static_cast<std::size_t>(std::max_element(run.x_mm.begin(), run.x_mm.end()) -
                                                run.x_mm.begin());
  const double depth = run.x_mm[deepest];
  if (depth <= kBin_mm) throw std::invalid_argument(run.source + ": no insertion to render");
  const auto bins = static_cast<std::size_t>(depth / kBin_mm) + 1;
  std::vector<double> sum(bins, 0.0), count(bins, 0.0);
  for (std::size_t i = 0; i <= deepest; ++i) {
    if (run.x_mm[i] < 0.0) continue;
    const auto b = std::min(bins - 1, static_cast<std::size_t>(run.x_mm[i] / kBin_mm));
    sum[b] += run.force_N[i];
    count[b] += 1.0;
  }
  table_.assign(bins, 0.0);
  double last = 0.0;
  for (std::size_t b = 0; b < bins; ++b) {  // empty bins (fast insertions) keep the last value
    if (count[b] > 0.0) last = sum[b] / count[b];
    table_[b] = last;
  }
}

double RecordedRunSource::insertion_force_N(double depth_mm) const noexcept {
  if (depth_mm <= 0.0 || table_.empty()) return 0.0;
  const double position = depth_mm / kBin_mm;
  const auto b = static_cast<std::size_t>(position);
  if (b + 1 >= table_.size()) return table_.back();
  const double w = position - static_cast<double>(b);
  return table_[b] * (1.0 - w) + table_[b + 1] * w;
}

double RecordedRunSource::force_N(double depth_mm, double front_mm,
                                  double /*velocity_mm_s*/) const noexcept {
  if (depth_mm >= front_mm) return insertion_force_N(depth_mm);
  return insertion_force_N(front_mm) * std::max(0.0, 1.0 - (front_mm - depth_mm) / kRelease_mm);
}

}  // namespace rig::haptic
