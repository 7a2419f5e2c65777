#include "segment_metrics.hpp"

#include <cmath>

namespace rig::model {

void MetricsAccumulator::add(double measured, double residual, double x_mm, double t_s,
                             const std::string& run) {
  ++m_.n;
  m_.sse_N2 += residual * residual;
  sum_y_ += measured;
  sum_y2_ += measured * measured;
  if (std::abs(residual) > m_.max_abs_N) {
    m_.max_abs_N = std::abs(residual);
    m_.max_at_x_mm = x_mm;
    m_.max_at_t_s = t_s;
    m_.max_in_run = run;
  }
}

SegmentMetrics MetricsAccumulator::finish() const {
  SegmentMetrics out = m_;
  if (out.n == 0) return out;
  const double n = static_cast<double>(out.n);
  const double sst = sum_y2_ - sum_y_ * sum_y_ / n;
  out.r2 = sst > 0.0 ? 1.0 - out.sse_N2 / sst : 0.0;
  out.rmse_N = std::sqrt(out.sse_N2 / n);
  return out;
}

}  // namespace rig::model
