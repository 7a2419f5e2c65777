#pragma once
// A lock-free tally of one latency (rig-sim's reply time, its physics clock's lateness): the
// largest value and how many passed 1 ms and 5 ms, so a loaded run can say where the time went
// when rigd saw no reply. Written by one thread, read by any (at exit).
#include <array>
#include <atomic>
#include <cstdint>
#include <string>

namespace rig::sim {

class LatencyTally {
 public:
  void record(std::int64_t ns) noexcept {
    count_.fetch_add(1, std::memory_order_relaxed);
    if (ns > max_ns_.load(std::memory_order_relaxed)) max_ns_.store(ns, std::memory_order_relaxed);
    if (ns >= 1'000'000) over_1ms_.fetch_add(1, std::memory_order_relaxed);
    if (ns >= 5'000'000) over_5ms_.fetch_add(1, std::memory_order_relaxed);
  }
  std::string summary() const {
    return "n=" + std::to_string(count_.load()) +
           " max_us=" + std::to_string(max_ns_.load() / 1000) +
           " over_1ms=" + std::to_string(over_1ms_.load()) +
           " over_5ms=" + std::to_string(over_5ms_.load());
  }

 private:
  std::atomic<std::uint64_t> count_{0};
  std::atomic<std::int64_t> max_ns_{0};
  std::atomic<std::uint64_t> over_1ms_{0};
  std::atomic<std::uint64_t> over_5ms_{0};
};

}  // namespace rig::sim
