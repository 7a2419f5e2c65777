#include "stall_watchdog.hpp"

namespace rig::haptic {

StallWatchdog::StallWatchdog(drivers::HapticDevice& device, std::chrono::milliseconds timeout, std::chrono::milliseconds poll)
    : device_(device), timeout_(timeout), poll_(poll) {}

StallWatchdog::~StallWatchdog() { stop(); }

void StallWatchdog::start() {
  if (timeout_.count() <= 0) return;  // off: no hand on a device (a simulated one on virtual time)
  stop_ = false;
  thread_ = std::thread([this] { run(); });
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
  std::uint64_t last_ticks = device_.ticks();
  Clock::time_point last_progress = Clock::now();
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, poll_, [this] { return stop_; })) {
    const std::uint64_t ticks = device_.ticks();
    const Clock::time_point now = Clock::now();
    if (ticks != last_ticks || !device_.running()) {
      last_ticks = ticks;
      last_progress = now;
      continue;
    }
    const double gap_ms = std::chrono::duration<double, std::milli>(now - last_progress).count();
    if (gap_ms > longest_gap_ms_.load()) longest_gap_ms_.store(gap_ms);
    if (now - last_progress > timeout_ && !tripped_.load()) {
      device_.force_off();
      tripped_.store(true);
    }
  }
}

}  // namespace rig::haptic
