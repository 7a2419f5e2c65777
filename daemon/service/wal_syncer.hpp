#pragma once
// Makes the recorder's commits durable off the recorder's thread. The archive commits with
// synchronous=NORMAL (Archive::defer_log_syncs: a commit is written to SQLite's log, not
// synced) and this thread fdatasyncs the log after each commit. So the two ways to lose
// samples are bounded apart:
//   - a crash or kill -9 takes only what was not yet written: at most one flush interval, even
//     while the disk takes 100 ms to sync (with synchronous=FULL the recorder waited for each
//     fsync before writing the next commit, and CI's durability test lost 127 ms, 2026-12-05);
//   - a power cut takes what was not yet synced: the exposure, measured per sync and reported.
// A synced log holds every commit written before the sync began: SQLite's recovery keeps the
// log's frames up to the last complete commit, so a sync never has to be atomic with a commit.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace rig::service {

class WalSyncer {
 public:
  using Clock = std::chrono::steady_clock;
  // Syncs the open log file; returns 0 or an errno value. fdatasync by default; tests slow it.
  using SyncFunction = std::function<int(int fd)>;

  // One commit written to the log and not yet known to be synced.
  struct Commit {
    Clock::time_point began;          // when its write began
    Clock::duration late{};           // how long after it was due it began
    Clock::time_point exposed_since;  // its oldest sample came after this (the previous commit's
                                      // start); the epoch: not known (rigd's first commit)
  };
  // One sync that ended: it made `commits` commits durable, the oldest first.
  struct Synced {
    std::uint64_t commits = 0;
    Clock::duration took{};      // the oldest one's start to the sync's end (write + sync)
    Clock::duration late{};      // how late the oldest one began
    Clock::duration exposure{};  // the oldest one's exposed_since to the sync's end
    bool has_exposure = false;   // false: the oldest one's exposed_since was not known
    std::string error;           // empty: synced; else what failed (the commits may be lost)
  };

  // log_path: SQLite's `<archive>-wal`, which exists once the archive is open in WAL mode.
  // Opens it now: a log that cannot be opened throws, naming the file (setup time).
  explicit WalSyncer(std::string log_path, SyncFunction sync = {});
  ~WalSyncer();
  WalSyncer(const WalSyncer&) = delete;
  WalSyncer& operator=(const WalSyncer&) = delete;

  // Starts the thread, SCHED_FIFO at `priority` when > 0; returns why that was refused.
  std::string start(int priority);
  // Syncs every commit written so far, then joins. Idempotent.
  void stop();

  // From the recorder's thread, right after a commit's write returned.
  void commit_written(const Commit& commit);
  // The syncs that ended since the last call (the recorder tallies them).
  std::vector<Synced> take_synced();
  // True once every commit written so far is synced.
  bool idle() const;

 private:
  void run();
  int sync_log();  // reopens the log if SQLite replaced it; 0 or errno
  int open_log();

  std::string log_path_;
  SyncFunction sync_;
  int fd_ = -1;
  std::thread thread_;
  mutable std::mutex mutex_;  // never taken by the RT thread: the recorder and this thread only
  std::condition_variable wake_;
  bool stop_ = false;
  bool syncing_ = false;
  std::vector<Commit> written_;  // written, not yet synced, oldest first
  std::vector<Synced> synced_;   // ended, not yet taken
};

}  // namespace rig::service
