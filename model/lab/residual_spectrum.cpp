#include "residual_spectrum.hpp"

#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <cmath>
#include <complex>

namespace rig::model {

void Spectrum::add(const std::vector<double>& axis, const std::vector<double>& residual,
                   double step, double max_frequency) {
  if (axis.size() < 16 || step <= 0.0) return;
  // Resample uniformly (linear interpolation) over the axis' range.
  std::vector<double> uniform;
  std::size_t j = 0;
  for (double a = axis.front(); a <= axis.back(); a += step) {
    while (j + 1 < axis.size() && axis[j + 1] < a) ++j;
    const double span = j + 1 < axis.size() ? axis[j + 1] - axis[j] : 0.0;
    const double w = span > 0.0 ? (a - axis[j]) / span : 0.0;
    uniform.push_back(j + 1 < axis.size() ? residual[j] * (1.0 - w) + residual[j + 1] * w
                                          : residual[j]);
  }
  double mean = 0.0;
  for (const double v : uniform) mean += v;
  mean /= static_cast<double>(uniform.size());
  for (double& v : uniform) v -= mean;
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> bins;
  fft.fwd(bins, uniform);
  const double n = static_cast<double>(uniform.size());
  const double resolution = 1.0 / (n * step);
  if (frequency.empty()) {
    for (double f = 0.0; f <= max_frequency; f += max_frequency / 2000.0) frequency.push_back(f);
    amplitude.assign(frequency.size(), 0.0);
  }
  for (std::size_t k = 0; k < frequency.size(); ++k) {
    const double position = frequency[k] / resolution;
    const auto bin = static_cast<std::size_t>(position);
    if (bin + 1 >= bins.size() / 2) break;
    const double w = position - static_cast<double>(bin);
    amplitude[k] += 2.0 / n * (std::abs(bins[bin]) * (1.0 - w) + std::abs(bins[bin + 1]) * w);
  }
  ++runs_;
}

void Spectrum::finish() {
  if (runs_ == 0) return;
  for (double& a : amplitude) a /= static_cast<double>(runs_);
}

std::vector<std::pair<double, double>> Spectrum::peaks(std::size_t count,
                                                       double min_frequency) const {
  std::vector<std::pair<double, double>> found;
  for (std::size_t k = 1; k + 1 < amplitude.size(); ++k) {
    if (frequency[k] < min_frequency) continue;
    if (amplitude[k] >= amplitude[k - 1] && amplitude[k] > amplitude[k + 1])
      found.emplace_back(frequency[k], amplitude[k]);
  }
  std::sort(found.begin(), found.end(),
            [](const auto& a, const auto& b) { return a.second > b.second; });
  if (found.size() > count) found.resize(count);
  return found;
}

}  // namespace rig::model
