#include "grid_line.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace rig::model {
namespace {

constexpr double kSearchHz = 0.3;       // half width of the search around the nominal [Hz]
constexpr double kCoarseStepHz = 0.02;  // under half the main lobe of a 40 s run (0.025 Hz)
constexpr double kFineToleranceHz = 0.001;

// |DFT| of the first differences (a high-pass: the force curve itself leaks no line) at
// `hz`, on a uniform grid of step dt_s: a phasor recurrence, no trigonometry per sample.
double line_power(const std::vector<double>& force_N, std::size_t begin, std::size_t end,
                  double dt_s, double hz) {
  const std::complex<double> step = std::polar(1.0, -2.0 * std::numbers::pi * hz * dt_s);
  std::complex<double> phasor(1.0, 0.0), sum(0.0, 0.0);
  for (std::size_t i = begin + 1; i < end; ++i) {
    sum += (force_N[i] - force_N[i - 1]) * phasor;
    phasor *= step;
    if (((i - begin) & 1023U) == 0U)
      phasor /= std::abs(phasor);  // keep |phasor| = 1 over long runs
  }
  return std::norm(sum);
}

}  // namespace

double grid_line_hz(const std::vector<double>& t_s, const std::vector<double>& force_N,
                    std::size_t begin, std::size_t end, double nominal_hz) {
  if (end > force_N.size() || end > t_s.size() || end < begin + 3) return nominal_hz;
  const double span_s = t_s[end - 1] - t_s[begin];
  const double dt_s = span_s / static_cast<double>(end - begin - 1);
  if (span_s < 2.0 || dt_s <= 0.0 || 1.0 / dt_s < 150.0) return nominal_hz;
  double best_hz = nominal_hz, best = -1.0;
  for (double hz = nominal_hz - kSearchHz; hz <= nominal_hz + kSearchHz + 1e-9;
       hz += kCoarseStepHz) {
    const double p = line_power(force_N, begin, end, dt_s, hz);
    if (p > best) best = p, best_hz = hz;
  }
  // Golden-section refinement inside the best coarse bin's neighbours.
  const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
  double lo = best_hz - kCoarseStepHz, hi = best_hz + kCoarseStepHz;
  double a = hi - ratio * (hi - lo), b = lo + ratio * (hi - lo);
  double pa = line_power(force_N, begin, end, dt_s, a),
         pb = line_power(force_N, begin, end, dt_s, b);
  while (hi - lo > kFineToleranceHz) {
    if (pa > pb) {
      hi = b, b = a, pb = pa, a = hi - ratio * (hi - lo),
      pa = line_power(force_N, begin, end, dt_s, a);
    } else {
      lo = a, a = b, pa = pb, b = lo + ratio * (hi - lo),
      pb = line_power(force_N, begin, end, dt_s, b);
    }
  }
  return 0.5 * (lo + hi);
}

std::vector<double> grid_cycles(const std::vector<double>& t_s, const std::vector<double>& force_N,
                                std::size_t begin, double line_hz) {
  constexpr double kHalfWindow_s = 0.5;
  const std::size_t n = std::min(t_s.size(), force_N.size());
  std::vector<double> cycles(n, 0.0);
  if (n == 0) return cycles;
  begin = std::min(begin, n - 1);
  for (std::size_t i = 0; i < n; ++i) cycles[i] = line_hz * (t_s[i] - t_s[begin]);
  if (n < begin + 3) return cycles;
  // Demodulated first differences, then their running sum for the moving average.
  std::vector<std::complex<double>> sum(n - begin + 1, {0.0, 0.0});
  for (std::size_t i = begin + 1; i < n; ++i) {
    const double d = force_N[i] - force_N[i - 1];
    sum[i - begin + 1] = sum[i - begin] + d * std::polar(1.0, -2.0 * std::numbers::pi * cycles[i]);
  }
  std::size_t lo = begin, hi = begin;
  double unwrapped = 0.0, previous = 0.0;
  bool first = true;
  for (std::size_t i = begin; i < n; ++i) {
    while (lo < i && t_s[lo] < t_s[i] - kHalfWindow_s) ++lo;
    while (hi + 1 < n && t_s[hi + 1] <= t_s[i] + kHalfWindow_s) ++hi;
    const std::complex<double> z = sum[hi - begin + 1] - sum[lo - begin];
    if (std::abs(z) <= 0.0) continue;
    const double angle = std::arg(z);
    if (first) {
      previous = angle, first = false;
    }
    double step = angle - previous;
    step -= 2.0 * std::numbers::pi * std::round(step / (2.0 * std::numbers::pi));
    unwrapped += step;
    previous = angle;
    cycles[i] += unwrapped / (2.0 * std::numbers::pi);
  }
  return cycles;
}

}  // namespace rig::model
