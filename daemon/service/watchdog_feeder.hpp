#pragma once
// Feeds systemd's watchdog only while the RT loop is alive: every half watchdog interval
// it asks `loop_alive` (did the loop complete cycles since the last question?) and sends
// WATCHDOG=1 only if so. A stalled loop stops the feeding, systemd kills rigd (SIGABRT)
// and restarts it; the DAQ's own watchdog has turned the motor off long before.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace rig::service {

class WatchdogFeeder {
 public:
  using Alive = std::function<bool()>;
  using Feed = std::function<void()>;
  using Report = std::function<void(const std::string&)>;  // STATUS= text when the loop stalls

  WatchdogFeeder(std::chrono::microseconds interval, Alive loop_alive, Feed feed, Report report);
  ~WatchdogFeeder();
  void start();
  void stop();
  std::uint64_t feeds() const { return feeds_.load(); }
  std::uint64_t missed() const { return missed_.load(); }

 private:
  void run();

  std::chrono::microseconds period_;
  Alive loop_alive_;
  Feed feed_;
  Report report_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::atomic<std::uint64_t> feeds_{0}, missed_{0};
};

}  // namespace rig::service
