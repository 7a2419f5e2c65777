#pragma once
// Sets and holds the intraocular pressure through the pump of the pressure line:
// feed-forward (target / full-scale) + PI, output clamped to [0, 1], and a settle detector
// (inside the band for the settle time) that gates the start of a cut.
#include "loop_settings.hpp"

namespace rig::rt {

class IopRegulator {
 public:
  explicit IopRegulator(const IopSettings& settings) : s_(settings) {}

  void set_target(double target_mmHg) noexcept;
  void disable() noexcept;
  // Returns the pump command [0..1].
  double update(double measured_mmHg, double dt_s) noexcept;

  bool active() const noexcept { return active_; }
  bool settled() const noexcept { return settled_; }
  double target_mmHg() const noexcept { return target_mmHg_; }
  double time_since_target_s() const noexcept { return since_target_s_; }

 private:
  IopSettings s_;
  bool active_ = false;
  bool settled_ = false;
  double target_mmHg_ = 0.0;
  double integral_ = 0.0;
  double in_band_s_ = 0.0;
  double since_target_s_ = 0.0;
};

}  // namespace rig::rt
