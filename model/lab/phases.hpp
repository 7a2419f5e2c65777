#pragma once
// Phases of a measured run, detected from the data alone (robust to noise, drift and
// irregular sampling): approach (x < 0), the cut - pre-cutting up to the puncture x_pi,
// cutting, unloading to x_pf, relaxation - then an optional hold at depth and the
// retraction.
#include <cstdint>
#include <string>
#include <vector>

#include "level_shifts.hpp"
#include "run_data.hpp"

namespace rig::model {

enum class Phase : std::uint8_t {
  kApproach,
  kPrecut,
  kCutting,
  kUnloading,
  kRelaxation,
  kHold,
  kRetraction
};
inline constexpr int kPhaseCount = 7;
const char* phase_name(Phase phase);

struct Segmentation {
  std::vector<Phase> phase;  // one per sample
  std::size_t insertion_end =
      0;  // where the insertion ended: the hold's first sample, else the deepest
  std::size_t hold_begin = 0, hold_end = 0;  // [begin, end) in samples; empty if no hold
  double x_pi_mm = 0.0;                      // detected puncture (0 if none)
  double x_c_mm = 0.0;                       // detected end of the cutting plateau
  double x_pf_mm = 0.0;                      // detected end of unloading
  double max_depth_mm = 0.0;
  double noise_sigma_N = 0.0;  // white-noise estimate of the force channel
  bool punctured = false;
  std::vector<OffsetStep>
      offset_steps;  // the force channel's zero jumps (level_shifts.hpp), in time order
  std::vector<std::string> notes;
};

Segmentation detect_phases(const RunData& run);

// Robust white-noise sigma of a signal: MAD of second differences (a smooth signal and
// slow drifts cancel, isolated jumps do not matter).
double noise_sigma(const std::vector<double>& values, std::size_t begin, std::size_t end);

// The median of `v` (the upper one of an even count); 0 when empty.
double median(std::vector<double> v);

}  // namespace rig::model
