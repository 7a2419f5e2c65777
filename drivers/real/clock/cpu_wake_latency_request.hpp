#pragma once
// Holds a PM QoS request on /dev/cpu_dma_latency for as long as the object lives: idle CPUs
// then stay in states they leave within `max_us` (0 = poll, never halt), as cyclictest does.
// On a VM an idle vCPU halts and exits to the host; waking it for a 1 kHz loop or for the
// DAQ's reply can then take longer than the loop's reply time-out. A DAQ with its own CPU
// never sleeps that deep, and neither may the CPUs the loop and the simulated DAQ share.
#include <string>

namespace rig::drivers {

class CpuWakeLatencyRequest {
 public:
  // max_us < 0: no request. Never throws; held() and why_not() tell whether it took effect.
  explicit CpuWakeLatencyRequest(int max_us);
  ~CpuWakeLatencyRequest();
  CpuWakeLatencyRequest(const CpuWakeLatencyRequest&) = delete;
  CpuWakeLatencyRequest& operator=(const CpuWakeLatencyRequest&) = delete;

  bool held() const { return fd_ >= 0; }
  const std::string& why_not() const { return why_not_; }

 private:
  int fd_ = -1;
  std::string why_not_;
};

}  // namespace rig::drivers
