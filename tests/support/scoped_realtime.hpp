#pragma once
// Makes the calling thread SCHED_FIFO for its scope (when allowed), so that a test's "read the
// DAQ's time, then act" is one step even on a busy machine that would take a normally
// scheduled test off the CPU in between and date the action too early.
#include <pthread.h>
#include <sched.h>

namespace rig::testing {

class ScopedRealtime {
 public:
  explicit ScopedRealtime(int priority = 60) {
    sched_param param{};
    param.sched_priority = priority;
    raised_ = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
  }
  ~ScopedRealtime() {
    if (!raised_) return;
    sched_param normal{};
    pthread_setschedparam(pthread_self(), SCHED_OTHER, &normal);
  }
  bool raised() const { return raised_; }  // false: refused (no privilege), normal scheduling
  ScopedRealtime(const ScopedRealtime&) = delete;
  ScopedRealtime& operator=(const ScopedRealtime&) = delete;

 private:
  bool raised_ = false;
};

}  // namespace rig::testing
