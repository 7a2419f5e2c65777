#pragma once
// How the recorder's commits go, for /api/status and /metrics. A run's samples are durable
// only once the commit after them has synced, so what a power cut can take is the longest
// span from one commit's start to the end of the next one's sync (the exposure). Two causes make it
// longer than the flush interval: a slow disk (commit time: write + fsync) and a recorder
// that gets the CPU late (lateness: how long after it was due a commit began). Written by the
// recorder thread only; read by the API.
#include <atomic>
#include <cstdint>

namespace rig::service {

struct RecorderStats {
  std::atomic<std::uint64_t> commits{0};          // commits written to the archive's log
  std::atomic<std::uint64_t> durable_commits{0};  // ... and synced since (wal_syncer.hpp)
  std::atomic<std::uint64_t> samples_written{0};
  std::atomic<std::int64_t> last_commit_us{0};  // the last synced commit's write + sync [us]
  std::atomic<std::int64_t> max_commit_us{0};   // the longest write + sync since rigd started [us]
  std::atomic<std::int64_t> max_late_us{0};     // the latest a commit began after it was due [us]
  std::atomic<std::int64_t> last_exposure_us{
      0};  // previous commit's start to the last one's end [us]
  std::atomic<std::int64_t> max_exposure_us{0};    // the longest such span since rigd started [us]
  std::atomic<std::uint64_t> checkpoints{0};       // the log copied into the database, between runs
  std::atomic<std::int64_t> max_checkpoint_us{0};  // the longest such copy [us]
};

}  // namespace rig::service
