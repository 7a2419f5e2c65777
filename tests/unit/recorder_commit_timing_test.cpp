// The recorder's commit tally (daemon/service/recorder_stats.hpp), which tells a slow disk from
// a starved recorder when a power cut loses more than one flush interval: every commit of
// samples is counted, a commit's exposure (the previous commit's start to its end) holds the
// commit itself, and an idle spell between runs is no exposure.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <random>
#include <thread>

#include "archive.hpp"
#include "commit_cadence.hpp"
#include "loop_channels.hpp"
#include "recorder.hpp"
#include "test_paths.hpp"

namespace rig::service {
namespace {

using namespace std::chrono_literals;
constexpr int kFlushIntervalMs = 20;

// Samples of one run, one per ms of wall time [cycle numbers continue from `cycle`].
void feed(rt::LoopChannels& channels, std::int64_t run_id, std::uint64_t& cycle,
          std::chrono::milliseconds how_long) {
  const auto end = std::chrono::steady_clock::now() + how_long;
  do {
    rt::Sample s;
    s.run_id = run_id;
    s.cycle = cycle;
    s.t_s = static_cast<double>(cycle) * 1e-3;
    ++cycle;
    ASSERT_TRUE(channels.recorder.try_push(s)) << "the recorder's ring filled";
    std::this_thread::sleep_for(1ms);
  } while (std::chrono::steady_clock::now() < end);
}

// Waits until the recorder has written `samples` and committed them (no commit for 5 intervals).
void until_committed(const Recorder& recorder, std::uint64_t samples) {
  const auto give_up = std::chrono::steady_clock::now() + 60s;
  while (recorder.samples_written() < samples && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(5ms);
  ASSERT_EQ(recorder.samples_written(), samples);
  for (std::uint64_t before = ~0ULL; before != recorder.commits();) {
    before = recorder.commits();
    std::this_thread::sleep_for(std::chrono::milliseconds(5 * kFlushIntervalMs));
  }
}

// A run in a new archive at `path`, started as the loop would have: its id.
std::int64_t started_run(const std::string& path, const char* eye_id) {
  archive::Archive archive(path);
  archive::NewRun run;
  run.eye_id = eye_id;
  const std::int64_t run_id = archive.create_run(run);
  archive.mark_started(run_id);
  return run_id;
}

// A scratch archive with a started run, and a recorder on it that has started.
struct RecordingArchive {
  RecordingArchive(const char* scratch, const char* eye_id)
      : dir(scratch),
        path((dir.path() / "archive.sqlite").string()),
        run_id(started_run(path, eye_id)),
        recorder(channels, path, kFlushIntervalMs) {
    recorder.start();
  }
  testing::ScratchDir dir;
  std::string path;
  std::int64_t run_id;
  rt::LoopChannels channels{1U << 14U};
  Recorder recorder;
};

TEST(RecorderCommitTiming, EveryCommitOfSamplesIsTalliedAndAnIdleSpellBetweenRunsIsNoExposure) {
  RecordingArchive rig("recorder-commit-timing", "TIMING");
  rt::LoopChannels& channels = rig.channels;
  Recorder& recorder = rig.recorder;
  const std::int64_t run_id = rig.run_id;
  std::uint64_t cycle = 0;
  ASSERT_NO_FATAL_FAILURE(feed(channels, run_id, cycle, 400ms));
  ASSERT_NO_FATAL_FAILURE(until_committed(recorder, cycle));
  const RecorderStats& stats = recorder.stats();
  EXPECT_GE(stats.commits.load(), 2U) << "400 ms of samples at a 20 ms flush interval";
  EXPECT_GT(stats.last_commit_us.load(), 0);
  EXPECT_GE(stats.max_commit_us.load(), stats.last_commit_us.load());
  EXPECT_GE(stats.max_late_us.load(), 0);
  EXPECT_GE(stats.last_exposure_us.load(), stats.last_commit_us.load())
      << "an exposure holds its own commit";
  EXPECT_GE(stats.max_exposure_us.load(), stats.last_exposure_us.load());

  // Between runs nothing is pending: the first commit after a 1.5 s idle spell is exposed from
  // the last check that found nothing to commit, not from the last commit before the spell.
  std::this_thread::sleep_for(1500ms);
  const std::uint64_t commits_before = stats.commits.load();
  ASSERT_NO_FATAL_FAILURE(feed(channels, run_id, cycle, 1ms));
  ASSERT_NO_FATAL_FAILURE(until_committed(recorder, cycle));
  EXPECT_EQ(stats.commits.load(), commits_before + 1);
  EXPECT_LT(stats.last_exposure_us.load(), 1'000'000)
      << "the idle spell was counted as exposure [us]";
  recorder.stop();
}

// SQLite copies its log into the database inside the commit that takes the log past 1000
// pages (~4 MB) unless told not to: a commit of hundreds of ms in the middle of a cut (the
// power-cut test's stalls). The recorder copies it only once no sample has come for a second.
TEST(RecorderCheckpoints, TheLogIsNeverCopiedInsideARunsCommitsButBetweenRuns) {
  RecordingArchive rig("recorder-checkpoints", "CHECKPOINTS");
  rt::LoopChannels& channels = rig.channels;
  Recorder& recorder = rig.recorder;
  const std::int64_t run_id = rig.run_id;
  const std::string& path = rig.path;
  std::this_thread::sleep_for(1500ms);  // the log the setup left is copied while idle
  const std::uint64_t checkpoints_before = recorder.stats().checkpoints.load();
  const std::uintmax_t database_before = std::filesystem::file_size(path);  // [B]
  // 250,000 samples make ~8 MB of log, twice the 1000 pages at which SQLite would copy it.
  std::uint64_t cycle = 0;
  constexpr std::uint64_t kSamples = 250'000;
  while (cycle < kSamples) {
    for (int n = 0; n < 2000; ++n, ++cycle) {  // a burst, then let the recorder drain it
      rt::Sample s;
      s.run_id = run_id;
      s.cycle = cycle;
      s.t_s = static_cast<double>(cycle) * 1e-3;
      while (!channels.recorder.try_push(s)) std::this_thread::sleep_for(1ms);
    }
    std::this_thread::sleep_for(5ms);
  }
  ASSERT_NO_FATAL_FAILURE(until_committed(recorder, cycle));
  EXPECT_EQ(recorder.stats().checkpoints.load(), checkpoints_before)
      << "copied the log while samples came";
  EXPECT_EQ(std::filesystem::file_size(path), database_before)
      << "the log was copied into the database inside a commit";
  EXPECT_GT(std::filesystem::file_size(path + "-wal"), 4U << 20U)
      << "the samples did not take the log past 1000 pages";
  const auto idle_until = std::chrono::steady_clock::now() + 10s;
  while (recorder.stats().checkpoints.load() == checkpoints_before &&
         std::chrono::steady_clock::now() < idle_until) {
    std::this_thread::sleep_for(50ms);
  }
  EXPECT_GT(recorder.stats().checkpoints.load(), checkpoints_before)
      << "no copy once the samples stopped";
  EXPECT_GT(std::filesystem::file_size(path), database_before)
      << "the copy between runs reached the database";
  recorder.stop();
  archive::Archive reader(path);
  EXPECT_EQ(reader.checkpoint(), 0) << "frames of the log were left uncopied";
  EXPECT_EQ(reader.load_run(run_id).size(), cycle) << "every sample is in the archive";
}

using Clock = CommitCadence::Clock;
constexpr auto kInterval = std::chrono::milliseconds(50);
constexpr auto kDrain = std::chrono::milliseconds(2);

TEST(CommitCadence, TheNextCommitStartsEarlyByTheRecentCostSoItsExposureStaysWithinTheInterval) {
  CommitCadence cadence(kInterval, kDrain);
  Clock::time_point warm{};  // kRecent cheap commits measured: the fresh assumption is gone
  for (std::size_t i = 0; i < CommitCadence::kRecent; ++i, warm += kInterval)
    cadence.after_commit(warm, warm, warm);
  const Clock::time_point t0 = warm + 1s;
  // Due at t0, began 5 ms late, took 10 ms: the next is due 50 - 2 - 15 ms after it began.
  const Clock::time_point began = t0 + 5ms;
  const Clock::time_point next = cadence.after_commit(t0, began, began + 10ms);
  EXPECT_EQ(next - began, 33ms);
  // A next commit no costlier (5 ms late, 10 ms long) ends within the interval of `began`,
  // less the drain period a sample can wait in the ring.
  EXPECT_LE((next + 5ms + 10ms) - began, kInterval - kDrain);
  // A commit longer than the interval: the next one is due at once, never before it ended.
  const Clock::time_point slow = t0 + 1s;
  EXPECT_EQ(cadence.after_commit(slow, slow, slow + 80ms), slow + 80ms);
  // The margin forgets: after kRecent cheap commits it is theirs again.
  Clock::time_point t = t0 + 2s;
  for (std::size_t i = 0; i < CommitCadence::kRecent; ++i, t += kInterval)
    cadence.after_commit(t, t, t + 1ms);
  EXPECT_EQ(cadence.recent_cost(), 1ms);
}

TEST(CommitCadence, AFreshCadenceAssumesACommitCostsHalfTheIntervalUntilItHasMeasuredSome) {
  CommitCadence cadence(kInterval, kDrain);
  EXPECT_EQ(cadence.recent_cost(), kInterval / 2);
  const Clock::time_point t0{};
  // A fresh rigd checks at t0 and finds nothing; the first samples come right after. Their
  // commit is due 50 - 2 - 25 ms later, so one of 20 ms (a commit under TCG) still ends within
  // the interval. With a margin of 0 it was due at 48 ms and ended at 68.
  const Clock::time_point first = cadence.after_empty_check(t0);
  EXPECT_EQ(first - t0, 23ms);
  EXPECT_LE((first + 20ms) - t0, kInterval - kDrain);
  // Once kRecent commits are measured the assumption is gone.
  Clock::time_point t = t0 + 1s;
  for (std::size_t i = 0; i < CommitCadence::kRecent; ++i, t += kInterval)
    cadence.after_commit(t, t, t + 3ms);
  EXPECT_EQ(cadence.recent_cost(), 3ms);
}

TEST(CommitCadence, ASyncSlowerThanHalfTheIntervalSpacesCommitsByHalfTheIntervalNotBackToBack) {
  CommitCadence cadence(kInterval, kDrain);
  Clock::time_point t{};
  for (std::size_t i = 0; i < CommitCadence::kRecent; ++i, t += kInterval)
    cadence.after_commit(t, t, t + 1ms);
  // The syncer reports a commit durable 200 ms after it was due (a stalled disk): no cadence
  // keeps the bound then, and writing every drain period would only load the disk more.
  cadence.note_durable(200ms);
  EXPECT_EQ(cadence.recent_cost(), 200ms);
  const Clock::time_point began = t + 1s;
  EXPECT_EQ(cadence.after_commit(began, began, began + 1ms) - began,
            kInterval - kDrain - kInterval / 2);
}

TEST(CommitCadence, NoCommitCostlierThanTheRecentOnesExposesMoreThanTheInterval) {
  CommitCadence cadence(kInterval, kDrain);
  std::mt19937 random(20261127);
  // Duration and lateness up to 10 ms each [us]: a commit and its margin fit in the interval
  // (beyond that no cadence can keep the bound: the disk is slower than the interval).
  std::uniform_int_distribution<int> cost_us(0, 10'000);
  Clock::time_point due{};
  Clock::time_point previous_began{};
  Clock::duration worst_exposure{};
  Clock::duration worst_cost{};
  for (int commit = 0; commit < 2000; ++commit) {
    const auto late = std::chrono::microseconds(cost_us(random));
    const auto took = std::chrono::microseconds(cost_us(random));
    const Clock::time_point began = due + late;
    const Clock::time_point ended = began + took;
    // Judged only while the margin already holds a cost as high as this one's.
    if (commit > 0 && late + took <= cadence.recent_cost())
      worst_exposure = std::max(worst_exposure, ended - previous_began);
    worst_cost = std::max(worst_cost, Clock::duration(late + took));
    due = cadence.after_commit(due, began, ended);
    previous_began = began;
  }
  EXPECT_GT(worst_exposure, Clock::duration::zero()) << "no commit was judged";
  EXPECT_LE(worst_exposure, kInterval - kDrain);
  EXPECT_GT(worst_cost, 15ms) << "the draw never came near its bound";
}

}  // namespace
}  // namespace rig::service
