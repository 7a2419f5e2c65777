#pragma once
// Drains the RT loop's recorder rings into the archive. Samples and events of a run are
// written in a transaction committed every flush interval, so a crash (even kill -9) loses
// at most that interval; each commit is synced on the syncer's thread (wal_syncer.hpp), so a
// power cut loses at most that interval too while the disk keeps up, and a slow disk delays
// only the sync, never the next write. Never touches the RT thread's data except through the
// rings.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "archive.hpp"
#include "commit_cadence.hpp"
#include "loop_channels.hpp"
#include "recorder_stats.hpp"
#include "wal_syncer.hpp"

namespace rig::service {

class Recorder {
 public:
  // sync: how the log is synced (fdatasync; tests slow it down).
  Recorder(rt::LoopChannels& channels, const std::string& archive_path, int flush_interval_ms,
           WalSyncer::SyncFunction sync = {});
  ~Recorder();
  // Starts the thread, with SCHED_FIFO at `priority` when > 0; returns why that was refused
  // (the recorder then runs with normal scheduling), empty when granted or not asked.
  std::string start(int priority = 0);
  void stop();  // drains what is left, commits, syncs, joins

  // Camera frame index rows, from the camera thread: written in the recorder's own
  // transaction, so the archive has a single writer and nobody waits on its lock.
  void add_frames(std::vector<archive::FrameRow> rows);
  std::uint64_t samples_written() const { return stats_.samples_written.load(); }
  std::uint64_t commits() const { return stats_.commits.load(); }
  const RecorderStats& stats() const { return stats_; }

 private:
  void run();
  void drain();
  void append_waiting_samples();  // every sample in the loop's ring now
  void ensure_transaction();      // opens the archive's transaction unless one is open
  void handle(const rt::Event& event);
  void flush();
  using Clock = std::chrono::steady_clock;
  // Commits once next_commit has come, sets the next one and tallies the commit's timing.
  void commit_when_due(Clock::time_point& next_commit);
  void tally_synced();  // the syncer's finished syncs into the stats and the cadence
  // Copies the archive's log into its database when no run is armed or cutting and no sample
  // came for a while: never inside a cut's commits (Archive::defer_checkpoints).
  void checkpoint_when_idle();

  rt::LoopChannels* channels_;
  std::unique_ptr<archive::Archive> archive_;
  int flush_interval_ms_;
  CommitCadence cadence_;
  std::unique_ptr<WalSyncer> syncer_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  RecorderStats stats_;
  std::int64_t armed_run_ = 0;
  std::int64_t open_run_ = 0;
  bool dirty_ = false;
  bool log_to_checkpoint_ =
      true;  // commits since the last checkpoint (or a log left by the last boot)
  Clock::time_point last_sample_{};  // when the last sample was drained
  Clock::time_point last_checkpoint_try_{};
  Clock::time_point previous_commit_began_{};  // for the exposure; epoch: none yet
  std::string last_fault_;
  std::mutex frames_mutex_;  // never taken by the RT thread
  std::vector<archive::FrameRow> pending_frames_;
};

// A fault with its measured value, in words ("force limit exceeded: 2.310 N").
std::string describe_fault(rt::FaultCode code, double value);

}  // namespace rig::service
