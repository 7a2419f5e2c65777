#pragma once
// Small helpers shared by the effect terms.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "prepared_run.hpp"

namespace rig::model::effects {

inline std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0,
                          double d = 0.0) {
  char text[512];
  std::snprintf(text, sizeof text, fmt, a, b, c, d);
  return text;
}

// Fourier columns sin/cos(2 pi k phase) for k = 1..harmonics into row[0..2*harmonics).
inline void fourier(double cycles, int harmonics, double* row) {
  // One sine and cosine, the higher harmonics by angle addition (exact to ~1e-15 over the
  // few harmonics used; sin/cos were a fifth of a diagnosis' time).
  const double a = 2.0 * std::numbers::pi * (cycles - std::floor(cycles));
  const double s1 = std::sin(a), c1 = std::cos(a);
  double s = s1, c = c1;
  for (int k = 1; k <= harmonics; ++k) {
    const std::ptrdiff_t column = 2 * static_cast<std::ptrdiff_t>(k - 1);
    row[column] = s;
    row[column + 1] = c;
    const double next_s = s * c1 + c * s1;
    c = c * c1 - s * s1;
    s = next_s;
  }
}

// Largest amplitude of the first harmonic over the runs' coefficient vectors [N].
// Per run: the amplitude of its first sine/cosine pair of coefficients (runs without one left out).
inline std::vector<double> run_amplitudes(const std::vector<Eigen::VectorXd>& coefficients) {
  std::vector<double> out;
  for (const auto& c : coefficients) {
    if (c.size() >= 2) out.push_back(std::hypot(c(0), c(1)));
  }
  return out;
}

inline double largest_amplitude(const std::vector<Eigen::VectorXd>& coefficients) {
  const std::vector<double> amplitudes = run_amplitudes(coefficients);
  return amplitudes.empty() ? 0.0 : *std::max_element(amplitudes.begin(), amplitudes.end());
}

inline bool is_tissue_phase(Phase p) {
  return p != Phase::kRetraction && p != Phase::kApproach;
}
inline bool after_puncture(Phase p) {
  return p == Phase::kCutting || p == Phase::kUnloading || p == Phase::kRelaxation ||
         p == Phase::kHold;
}

}  // namespace rig::model::effects
