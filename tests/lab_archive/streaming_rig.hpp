#pragma once
// One simulated rig for the lab-archive benchmark: a thread that records a run into its own
// SQLite archive at the loop rate with every channel, committing a batch each flush period
// as rigd's recorder does, and remembers when each batch became visible locally.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "archive.hpp"
#include "local_run_writer.hpp"

namespace rig::testing {

class StreamingRig {
 public:
  using Clock = std::chrono::steady_clock;
  struct Commit {
    std::int64_t last_idx;
    Clock::time_point at;
  };

  StreamingRig(const std::string& path, double rate_hz, int flush_ms)
      : archive_(path), writer_(archive_), rate_hz_(rate_hz), flush_ms_(flush_ms) {
    run_id_ = writer_.start("bench", "L-bench");
  }
  ~StreamingRig() { stop(); }
  void start() {
    thread_ = std::thread([this] { loop(); });
  }
  void stop() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }
  void finish() { writer_.finish(run_id_); }
  std::vector<Commit> commits() {
    std::lock_guard lock(mutex_);
    return commits_;
  }
  std::int64_t samples() const { return written_; }
  const std::string& path() const { return archive_.path(); }
  // Writes `count` samples at once (a backlog, as after a long network cut).
  void append_now(std::int64_t count) {
    writer_.append(run_id_, count);
    written_ += count;
  }

 private:
  void loop() {
    const auto period = std::chrono::milliseconds(flush_ms_);
    const auto per_batch = static_cast<std::int64_t>(rate_hz_ * flush_ms_ / 1000.0);
    auto next = Clock::now();
    while (running_) {
      next += period;
      std::this_thread::sleep_until(next);
      writer_.append(run_id_, per_batch);
      written_ += per_batch;
      std::lock_guard lock(mutex_);
      commits_.push_back({first_idx_ + written_ - 1, Clock::now()});
    }
  }

  archive::Archive archive_;
  LocalRunWriter writer_;
  double rate_hz_;
  int flush_ms_;
  std::int64_t run_id_ = 0;
  const std::int64_t first_idx_ = 1000;  // LocalRunWriter's first cycle
  std::atomic<std::int64_t> written_{0};
  std::atomic<bool> running_{true};
  std::mutex mutex_;
  std::vector<Commit> commits_;
  std::thread thread_;
};

}  // namespace rig::testing
