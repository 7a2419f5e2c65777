#pragma once
// Haptic fidelity, as the paper measures it: the force the (simulated) hand felt against a
// reference force source evaluated at the hand's true position (true depth, the deepest
// true depth so far, the true velocity). Only ticks in contact (true depth > 0) count.
#include <cstddef>
#include <vector>

#include "force_source.hpp"
#include "sim_phantom.hpp"

namespace rig::haptic {

struct ErrorFigures {
  double rmse_N = 0.0;
  double max_N = 0.0;
  double max_at_depth_mm = 0.0;
  std::size_t samples = 0;
};

ErrorFigures felt_error(const std::vector<drivers::FeltSample>& felt, const ForceSource& reference);

}  // namespace rig::haptic
