#pragma once
// Drains the RT loop's recorder rings into the archive. Samples and events of a run are
// written in a transaction committed every flush interval, so a crash (even kill -9) loses
// at most that interval. Never touches the RT thread's data except through the rings.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>
#include <string>
#include <thread>

#include "archive.hpp"
#include "loop_channels.hpp"

namespace rig::service {

class Recorder {
 public:
  Recorder(rt::LoopChannels& channels, const std::string& archive_path, int flush_interval_ms);
  ~Recorder();
  void start();
  void stop();  // drains what is left, commits, joins

  // Camera frame index rows, from the camera thread: written in the recorder's own
  // transaction, so the archive has a single writer and nobody waits on its lock.
  void add_frames(std::vector<archive::FrameRow> rows);
  std::uint64_t samples_written() const { return samples_written_.load(); }
  std::uint64_t commits() const { return commits_.load(); }

 private:
  void run();
  std::size_t drain();
  void handle(const rt::Event& event);
  void flush();

  rt::LoopChannels* channels_;
  std::unique_ptr<archive::Archive> archive_;
  int flush_interval_ms_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> samples_written_{0};
  std::atomic<std::uint64_t> commits_{0};
  std::int64_t armed_run_ = 0;
  std::int64_t open_run_ = 0;
  bool dirty_ = false;
  std::string last_fault_;
  std::mutex frames_mutex_;  // never taken by the RT thread
  std::vector<archive::FrameRow> pending_frames_;
};

// A fault with its measured value, in words ("force limit exceeded: 2.310 N").
std::string describe_fault(rt::FaultCode code, double value);

}  // namespace rig::service
