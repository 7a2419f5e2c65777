#pragma once
// Faults of the loop's timing (the DAQ link, writes lost to late replies, the DAQ's watchdog,
// loop overruns), by the text
// rigd reports (rt::to_string of the fault code, then details). On a real rig a fault of the
// machine; on the simulated rig sharing a busy machine's CPUs, what the demo and the test
// harness name and retry (docs/faults.md).
#include <string>

namespace rig::cli {

inline bool is_timing_fault(const std::string& fault) {
  // Writes *lost* (no valid answer in time) are the link's timing; writes *refused* by the DAQ
  // (a Modbus exception) are not, and are never retried.
  const bool writes_lost = fault.rfind("DAQ write failed", 0) == 0 &&
                           fault.find("writes in a row lost") != std::string::npos;
  return fault.rfind("DAQ link lost", 0) == 0 || fault.rfind("DAQ watchdog tripped", 0) == 0 ||
         fault.rfind("loop overrun storm", 0) == 0 || writes_lost;
}

}  // namespace rig::cli
