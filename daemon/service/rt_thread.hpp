#pragma once
// Real-time thread setup, done once in main before the loop starts (ros2_control style):
// mlockall, SCHED_FIFO at the configured priority, CPU affinity. Each step that the OS
// refuses (no CAP_SYS_NICE, RLIMIT_MEMLOCK) is a warning, never a failure: the loop still
// runs, just with more jitter, and the status says so.
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace rig::service {

struct RtThreadOptions {
  int priority = 80;  // 0 = normal scheduling
  int cpu = -1;
  bool lock_memory = true;
  const char* name =
      "rigd-loop";  // the thread's name (15 characters at most): `top -H`, `ps -L`, the tests
};

struct RtThreadReport {
  bool memory_locked = false;
  bool memory_locked_on_fault = false;  // a sanitizer build: each page locks when first touched
  bool realtime = false;
  bool pinned = false;
  std::vector<std::string> warnings;
};

// Locks memory for the whole process (call before starting other threads).
RtThreadReport lock_process_memory(bool lock);
// Starts `body` on a thread with the RT attributes; fills report.realtime/pinned.
std::thread start_rt_thread(const RtThreadOptions& options, std::function<void()> body,
                            RtThreadReport& report);

}  // namespace rig::service
