#include "rt_thread.hpp"

#include <pthread.h>
#include <sched.h>

#include <cstring>
#include <future>

#include "clock/process_memory_lock.hpp"

namespace rig::service {

RtThreadReport lock_process_memory(bool lock) {
  RtThreadReport report;
  if (!lock) return report;
  const drivers::ProcessMemoryLock memory = drivers::lock_process_memory_in_ram();
  report.memory_locked = memory.locked;
  report.memory_locked_on_fault = memory.locked && memory.on_fault_only;
  if (!memory.locked) {
    report.warnings.push_back("mlockall failed (" + memory.error +
                              "): page faults may delay the loop; raise LimitMEMLOCK");
  }
  return report;
}

std::thread start_rt_thread(const RtThreadOptions& options, std::function<void()> body,
                            RtThreadReport& report) {
  // The body waits until name, priority and CPU are set: its first cycle already runs as
  // configured.
  std::promise<void> configured;
  std::thread thread([body = std::move(body), go = configured.get_future()]() mutable {
    go.wait();
    body();
  });
  const pthread_t handle = thread.native_handle();
  pthread_setname_np(handle, options.name);
  if (options.priority > 0) {
    sched_param param{};
    param.sched_priority = options.priority;
    const int rc = pthread_setschedparam(handle, SCHED_FIFO, &param);
    if (rc == 0) {
      report.realtime = true;
    } else {
      report.warnings.push_back(
          "SCHED_FIFO priority " + std::to_string(options.priority) + " refused (" +
          std::strerror(rc) +
          "): the loop runs with normal scheduling; grant CAP_SYS_NICE / LimitRTPRIO");
    }
  }
  if (options.cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(static_cast<unsigned>(options.cpu), &set);
    const int rc = pthread_setaffinity_np(handle, sizeof set, &set);
    if (rc == 0) {
      report.pinned = true;
    } else {
      report.warnings.push_back("pinning the loop to CPU " + std::to_string(options.cpu) +
                                " failed: " + std::strerror(rc));
    }
  }
  configured.set_value();
  return thread;
}

}  // namespace rig::service
