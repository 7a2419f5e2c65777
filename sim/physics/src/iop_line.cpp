#include "rig/sim/iop_line.hpp"

#include <algorithm>

namespace rig::sim {

void IopLine::step(double dt_s, double pump_command, bool punctured, double extra_leak) {
  const double leak = std::clamp((punctured ? p_.leak_after_puncture : 0.0) + extra_leak, 0.0, 1.0);
  const double steady_mmHg = std::clamp(pump_command, 0.0, 1.0) * p_.pump_max_mmHg * (1.0 - leak);
  pressure_mmHg_ += (steady_mmHg - pressure_mmHg_) * std::min(1.0, dt_s / p_.time_constant_s);
}

}  // namespace rig::sim
