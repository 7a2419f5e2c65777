#pragma once
// Every safety check of one cycle. The first that applies wins; the loop turns it into a
// fault in the same cycle, so the motor is off before the next period starts.
#include "cycle_types.hpp"
#include "loop_settings.hpp"
#include "run_state_machine.hpp"

namespace rig::rt {

struct InterlockVerdict {
  FaultCode code = FaultCode::kNone;
  double value = 0.0;  // what tripped it: force [N], position [mm], misses, ...
};

class Interlocks {
 public:
  // Output writes failed in a row (reads answered) before the run faults:
  // safety.max_failed_writes (default 3). An explicit refusal counts as all of them: the fault
  // comes in the next cycle, before the DAQ's own watchdog (daq.watchdog_ms = 5) trips.
  explicit Interlocks(const LoopSettings& settings) : s_(settings) {}
  InterlockVerdict check(const CycleInput& in, const RunStateMachine& machine,
                         double following_error_mm) noexcept;

 private:
  InterlockVerdict check_motion(const CycleInput& in, const RunStateMachine& machine,
                                double following_error_mm) noexcept;
  InterlockVerdict check_daq(const CycleInput& in) noexcept;
  bool force_channel_stuck(const CycleInput& in, const RunStateMachine& machine) noexcept;
  bool iop_out_of_band(const CycleInput& in, const RunStateMachine& machine) noexcept;

  LoopSettings s_;
  int identical_force_cycles_ = 0;
  double last_force_volts_ = 0.0;
  double iop_out_of_band_s_ = 0.0;  // how long the IOP has been outside its band in this cut [s]
};

}  // namespace rig::rt
