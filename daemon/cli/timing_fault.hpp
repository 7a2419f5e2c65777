#pragma once
// Faults of the loop's timing (the DAQ link, the DAQ's watchdog, loop overruns), by the text
// rigd reports (rt::to_string of the fault code, then details). On a real rig a fault of the
// machine; on the simulated rig sharing a busy machine's CPUs, what the demo and the test
// harness name and retry (docs/faults.md).
#include <string>

namespace rig::cli {

inline bool is_timing_fault(const std::string& fault) {
  return fault.rfind("DAQ link lost", 0) == 0 || fault.rfind("DAQ watchdog tripped", 0) == 0 ||
         fault.rfind("loop overrun storm", 0) == 0;
}

}  // namespace rig::cli
