#pragma once
// Small helpers shared by the effect terms.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "prepared_run.hpp"

namespace rig::model::effects {

inline std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char text[512];
  std::snprintf(text, sizeof text, fmt, a, b, c, d);
  return text;
}

// Fourier columns sin/cos(2 pi k phase) for k = 1..harmonics into row[0..2*harmonics).
inline void fourier(double cycles, int harmonics, double* row) {
  for (int k = 1; k <= harmonics; ++k) {
    const double a = 2.0 * std::numbers::pi * k * cycles;
    row[2 * (k - 1)] = std::sin(a);
    row[2 * (k - 1) + 1] = std::cos(a);
  }
}

// Largest amplitude of the first harmonic over the runs' coefficient vectors [N].
inline double largest_amplitude(const std::vector<Eigen::VectorXd>& coefficients) {
  double best = 0.0;
  for (const auto& c : coefficients) {
    if (c.size() >= 2) best = std::max(best, std::hypot(c(0), c(1)));
  }
  return best;
}

inline bool is_tissue_phase(Phase p) { return p != Phase::kRetraction && p != Phase::kApproach; }
inline bool after_puncture(Phase p) {
  return p == Phase::kCutting || p == Phase::kUnloading || p == Phase::kRelaxation || p == Phase::kHold;
}

}  // namespace rig::model::effects
