#include "felt_error.hpp"

#include <algorithm>
#include <cmath>

namespace rig::haptic {

ErrorFigures felt_error(const std::vector<drivers::FeltSample>& felt,
                        const ForceSource& reference) {
  ErrorFigures figures;
  double sum_sq = 0.0;
  double front = -1e9;
  for (std::size_t i = 0; i < felt.size(); ++i) {
    const drivers::FeltSample& s = felt[i];
    front = std::max(front, s.depth_mm);
    if (s.depth_mm <= 0.0) continue;
    const double dt = i > 0 ? s.t_s - felt[i - 1].t_s : 0.0;
    const double velocity = dt > 0.0 ? (s.depth_mm - felt[i - 1].depth_mm) / dt : 0.0;
    const double error = std::abs(s.force_N - reference.force_N(s.depth_mm, front, velocity));
    sum_sq += error * error;
    if (error > figures.max_N) figures.max_N = error, figures.max_at_depth_mm = s.depth_mm;
    ++figures.samples;
  }
  if (figures.samples > 0)
    figures.rmse_N = std::sqrt(sum_sq / static_cast<double>(figures.samples));
  return figures;
}

}  // namespace rig::haptic
