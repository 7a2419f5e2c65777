// The recorder writes each commit to the archive's log and a second thread syncs it
// (daemon/service/wal_syncer.hpp). So a disk that takes long to sync delays only durability,
// never the next write: a kill -9 of rigd loses at most one flush interval whatever the disk
// does. A sync that fails faults the run. The syncs here are held or failed on purpose.
#include <gtest/gtest.h>

#include <unistd.h>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "archive.hpp"
#include "loop_channels.hpp"
#include "recorder.hpp"
#include "sqlite_handle.hpp"
#include "test_paths.hpp"

namespace rig::service {
namespace {

using namespace std::chrono_literals;
constexpr int kSlowDiskFlushIntervalMs = 20;

// A sync the test holds until it lets go: the disk "stalls" for as long as the test wants.
class HeldSync {
 public:
  int operator()(int fd) {
    std::unique_lock lock(mutex_);
    ++started_;
    released_.wait(lock, [this] { return open_; });
    return ::fdatasync(fd) == 0 ? 0 : errno;
  }
  void release() {
    {
      const std::lock_guard lock(mutex_);
      open_ = true;
    }
    released_.notify_all();
  }
  int started() {
    const std::lock_guard lock(mutex_);
    return started_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable released_;
  bool open_ = false;
  int started_ = 0;
};

std::int64_t slow_disk_run(const std::string& path) {
  archive::Archive archive(path);
  archive::NewRun run;
  run.eye_id = "SLOW-DISK";
  const std::int64_t run_id = archive.create_run(run);
  archive.mark_started(run_id);
  return run_id;
}

void push_slow_disk_samples(rt::LoopChannels& channels, std::int64_t run_id, std::uint64_t& cycle,
                            int count) {
  for (int i = 0; i < count; ++i, ++cycle) {
    rt::Sample s;
    s.run_id = run_id;
    s.cycle = cycle;
    s.t_s = static_cast<double>(cycle) * 1e-3;
    while (!channels.recorder.try_push(s)) std::this_thread::sleep_for(1ms);
  }
}

// The samples of the run another connection can read (written to the log, synced or not).
std::int64_t slow_disk_samples_readable(const std::string& path, std::int64_t run_id) {
  archive::Database db(path, true);
  auto q = db.prepare("SELECT COUNT(*) FROM samples WHERE run_id = ?");
  q.bind(1, run_id);
  q.step();
  return q.integer(0);
}

bool slow_disk_eventually(const std::function<bool()>& done) {
  const auto give_up = std::chrono::steady_clock::now() + 30s;
  while (!done() && std::chrono::steady_clock::now() < give_up) std::this_thread::sleep_for(5ms);
  return done();
}

TEST(RecorderWithASlowDisk,
     KeepsWritingCommitsWhileASyncIsStuckAndSyncsThemAllWhenTheDiskComesBack) {
  testing::ScratchDir dir("recorder-slow-sync");
  const std::string path = (dir.path() / "archive.sqlite").string();
  const std::int64_t run_id = slow_disk_run(path);
  rt::LoopChannels channels{1U << 14U};
  HeldSync held;
  Recorder recorder(channels, path, kSlowDiskFlushIntervalMs, [&held](int fd) { return held(fd); });
  struct ReleaseOnExit {
    HeldSync& sync;
    ~ReleaseOnExit() {
      sync.release();
    }  // before the recorder stops: a failed assertion never hangs
  } release_on_exit{held};
  recorder.start();
  std::uint64_t cycle = 0;
  push_slow_disk_samples(channels, run_id, cycle, 100);
  ASSERT_TRUE(slow_disk_eventually([&] { return held.started() == 1; }))
      << "the first commit was never synced";
  // The disk holds the first sync. Samples keep coming: they are written in later commits,
  // readable by another connection, while nothing is durable yet.
  const std::uint64_t commits_at_stall = recorder.commits();
  for (int burst = 0; burst < 10; ++burst) {
    push_slow_disk_samples(channels, run_id, cycle, 20);
    std::this_thread::sleep_for(std::chrono::milliseconds(kSlowDiskFlushIntervalMs));
  }
  ASSERT_TRUE(slow_disk_eventually([&] {
    return slow_disk_samples_readable(path, run_id) == static_cast<std::int64_t>(cycle);
  })) << "samples written after the stall began are not in the log: the writes waited for the sync";
  EXPECT_GE(recorder.commits(), commits_at_stall + 2)
      << "no commit was written while the sync was stuck";
  EXPECT_EQ(recorder.stats().durable_commits.load(), 0U)
      << "a commit counted durable before its sync ended";
  EXPECT_EQ(held.started(), 1) << "a second sync began beside the stuck one";
  held.release();
  recorder.stop();
  EXPECT_EQ(recorder.stats().durable_commits.load(), recorder.commits())
      << "a written commit was never synced";
  // The exposure counts the stall: honest about what a power cut could have taken meanwhile.
  EXPECT_GE(recorder.stats().max_exposure_us.load(), 200'000)
      << "the stuck sync is not in the exposure [us]";
  EXPECT_EQ(channels.service_fault.load(), rt::FaultCode::kNone);
}

TEST(RecorderWithASlowDisk, ASyncThatFailsFaultsTheRun) {
  testing::ScratchDir dir("recorder-failed-sync");
  const std::string path = (dir.path() / "archive.sqlite").string();
  const std::int64_t run_id = slow_disk_run(path);
  rt::LoopChannels channels{1U << 14U};
  Recorder recorder(channels, path, kSlowDiskFlushIntervalMs, [](int) { return EIO; });
  recorder.start();
  std::uint64_t cycle = 0;
  push_slow_disk_samples(channels, run_id, cycle, 100);
  EXPECT_TRUE(slow_disk_eventually([&] {
    return channels.service_fault.load() == rt::FaultCode::kArchiveWriteFailed;
  })) << "an I/O error on the log's sync went unnoticed";
  recorder.stop();
  EXPECT_EQ(recorder.stats().durable_commits.load(), 0U);
}

}  // namespace
}  // namespace rig::service
