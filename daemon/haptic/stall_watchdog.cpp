#include "stall_watchdog.hpp"

#include <pthread.h>
#include <sched.h>

#include "servo_silence.hpp"

namespace rig::haptic {

namespace {
constexpr int kWatchdogPriority = 85;  // SCHED_FIFO
}  // namespace

StallWatchdog::StallWatchdog(drivers::HapticDevice& device, std::chrono::milliseconds timeout,
                             std::chrono::milliseconds poll)
    : device_(device), timeout_(timeout), poll_(poll) {}

StallWatchdog::~StallWatchdog() {
  stop();
}

void StallWatchdog::start() {
  if (timeout_.count() <= 0) return;  // off: no hand on a device (a simulated one on virtual time)
  stop_ = false;
  thread_ = std::thread([this] { run(); });
  // Above the servo's SCHED_FIFO 80 (and rig-sim's 81): a watchdog of normal priority woke late
  // on a busy machine, and a late watchdog judges late. Best effort: without CAP_SYS_NICE it
  // runs at normal priority, and its late wake-ups are excused (ServoSilence).
  sched_param param{};
  param.sched_priority = kWatchdogPriority;
  pthread_setschedparam(thread_.native_handle(), SCHED_FIFO, &param);
}

void StallWatchdog::stop() noexcept {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void StallWatchdog::run() noexcept {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  auto now_ms = [start] {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  };
  ServoSilence silence(std::chrono::duration<double, std::milli>(poll_).count());
  silence.poll(now_ms(), device_.ticks(), device_.running());
  const double timeout_ms = std::chrono::duration<double, std::milli>(timeout_).count();
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, poll_, [this] { return stop_; })) {
    const double gap_ms = silence.poll(now_ms(), device_.ticks(), device_.running());
    if (gap_ms > longest_gap_ms_.load()) longest_gap_ms_.store(gap_ms);
    if (gap_ms > timeout_ms && !tripped_.load()) {
      device_.force_off();
      tripped_.store(true);
    }
  }
}

}  // namespace rig::haptic
