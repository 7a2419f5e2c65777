#pragma once
// A recorded run as a force-displacement lookup: the insertion's force, averaged in 0.02 mm
// bins of depth (the load cell's noise is not rendered), interpolated linearly; withdrawn
// from the deepest point the force is released over 0.2 mm, as the model does.
#include <vector>

#include "force_source.hpp"
#include "run_data.hpp"

namespace rig::haptic {

class RecordedRunSource final : public ForceSource {
 public:
  explicit RecordedRunSource(const model::RunData& run);  // throws if the run has no insertion
  double force_N(double depth_mm, double front_mm, double velocity_mm_s) const noexcept override;
  const char* describe() const noexcept override { return "recorded run"; }
  double insertion_force_N(double depth_mm) const noexcept;

 private:
  static constexpr double kBin_mm = 0.02;
  static constexpr double kRelease_mm = 0.2;
  std::vector<double> table_;  // force at depth k * kBin_mm
};

}  // namespace rig::haptic
