#pragma once
// Amplitude spectrum of residuals, averaged over runs on a common axis: in time (uniform
// resampling at the median sample interval) or in displacement (uniform in x over the
// insertion). Irregular sampling is interpolated, never dropped.
#include <vector>

namespace rig::model {

struct Spectrum {
  std::vector<double> frequency;  // [Hz] or [1/mm]
  std::vector<double> amplitude;  // [N]
  void add(const std::vector<double>& axis, const std::vector<double>& residual, double step,
           double max_frequency);
  void finish();
  // Largest local maxima above min_frequency, strongest first.
  std::vector<std::pair<double, double>> peaks(std::size_t count, double min_frequency) const;

 private:
  std::size_t runs_ = 0;
};

}  // namespace rig::model
