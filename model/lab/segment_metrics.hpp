#pragma once
// The paper's goodness-of-fit figures per segment (SSE, R^2, RMSE), plus the largest error
// and where it occurs.
#include <string>
#include <vector>

namespace rig::model {

struct SegmentMetrics {
  std::string segment;
  std::size_t n = 0;
  double sse_N2 = 0.0;
  double r2 = 0.0;  // 1 - SSE/SST (can be low on flat segments, as the paper notes)
  double rmse_N = 0.0;
  double max_abs_N = 0.0;
  double max_at_x_mm = 0.0;
  double max_at_t_s = 0.0;
  std::string max_in_run;
};

class MetricsAccumulator {
 public:
  explicit MetricsAccumulator(std::string segment) { m_.segment = std::move(segment); }
  void add(double measured, double residual, double x_mm, double t_s, const std::string& run);
  SegmentMetrics finish() const;

 private:
  SegmentMetrics m_;
  double sum_y_ = 0.0, sum_y2_ = 0.0;
};

}  // namespace rig::model
