#pragma once
// Pressure line holding the intraocular pressure: a pump into a compliant eye with a
// first-order response; the incision leaks a little once the cornea is punctured.
#include "rig/sim/physics_params.hpp"

namespace rig::sim {

class IopLine {
 public:
  explicit IopLine(const IopLineParams& params) : p_(params), pressure_mmHg_(params.initial_mmHg) {}
  // extra_leak: an injected leak (0..1), on top of the puncture's own.
  void step(double dt_s, double pump_command, bool punctured, double extra_leak = 0.0);
  double pressure_mmHg() const { return pressure_mmHg_; }
  void set_pressure_mmHg(double pressure) { pressure_mmHg_ = pressure; }

 private:
  IopLineParams p_;
  double pressure_mmHg_;
};

}  // namespace rig::sim
