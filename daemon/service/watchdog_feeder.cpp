#include "watchdog_feeder.hpp"

namespace rig::service {

WatchdogFeeder::WatchdogFeeder(std::chrono::microseconds interval, Alive loop_alive, Feed feed,
                               Report report)
    : period_(interval / 2),
      loop_alive_(std::move(loop_alive)),
      feed_(std::move(feed)),
      report_(std::move(report)) {}

WatchdogFeeder::~WatchdogFeeder() {
  stop();
}

void WatchdogFeeder::start() {
  if (period_.count() <= 0 || thread_.joinable()) return;
  thread_ = std::thread([this] { run(); });
}

void WatchdogFeeder::stop() {
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void WatchdogFeeder::run() {
  bool was_alive = true;
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, period_, [this] { return stop_; })) {
    const bool alive = loop_alive_();
    if (alive) {
      feed_();
      feeds_.fetch_add(1);
    } else {
      missed_.fetch_add(1);
      if (was_alive) report_("RT loop stalled: watchdog not fed");
    }
    was_alive = alive;
  }
}

}  // namespace rig::service
