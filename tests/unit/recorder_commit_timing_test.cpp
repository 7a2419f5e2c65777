// The recorder's commit tally (daemon/service/recorder_stats.hpp), which tells a slow disk from
// a starved recorder when a power cut loses more than one flush interval: every commit of
// samples is counted, a commit's exposure (the previous commit's start to its end) holds the
// commit itself, and an idle spell between runs is no exposure.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "archive.hpp"
#include "loop_channels.hpp"
#include "recorder.hpp"
#include "test_paths.hpp"

namespace rig::service {
namespace {

using namespace std::chrono_literals;
constexpr int kFlushIntervalMs = 20;

// Samples of one run, one per ms of wall time [cycle numbers continue from `cycle`].
void feed(rt::LoopChannels& channels, std::int64_t run_id, std::uint64_t& cycle, std::chrono::milliseconds how_long) {
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
  while (recorder.samples_written() < samples && std::chrono::steady_clock::now() < give_up) std::this_thread::sleep_for(5ms);
  ASSERT_EQ(recorder.samples_written(), samples);
  for (std::uint64_t before = ~0ULL; before != recorder.commits();) {
    before = recorder.commits();
    std::this_thread::sleep_for(std::chrono::milliseconds(5 * kFlushIntervalMs));
  }
}

TEST(RecorderCommitTiming, EveryCommitOfSamplesIsTalliedAndAnIdleSpellBetweenRunsIsNoExposure) {
  testing::ScratchDir dir("recorder-commit-timing");
  const std::string path = (dir.path() / "archive.sqlite").string();
  std::int64_t run_id = 0;
  {
    archive::Archive archive(path);
    archive::NewRun run;
    run.eye_id = "TIMING";
    run_id = archive.create_run(run);
    archive.mark_started(run_id);
  }
  rt::LoopChannels channels(1U << 14U);
  Recorder recorder(channels, path, kFlushIntervalMs);
  recorder.start();
  std::uint64_t cycle = 0;
  ASSERT_NO_FATAL_FAILURE(feed(channels, run_id, cycle, 400ms));
  ASSERT_NO_FATAL_FAILURE(until_committed(recorder, cycle));
  const RecorderStats& stats = recorder.stats();
  EXPECT_GE(stats.commits.load(), 2U) << "400 ms of samples at a 20 ms flush interval";
  EXPECT_GT(stats.last_commit_us.load(), 0);
  EXPECT_GE(stats.max_commit_us.load(), stats.last_commit_us.load());
  EXPECT_GE(stats.max_late_us.load(), 0);
  EXPECT_GE(stats.last_exposure_us.load(), stats.last_commit_us.load()) << "an exposure holds its own commit";
  EXPECT_GE(stats.max_exposure_us.load(), stats.last_exposure_us.load());

  // Between runs nothing is pending: the first commit after a 1.5 s idle spell is exposed from
  // the last check that found nothing to commit, not from the last commit before the spell.
  std::this_thread::sleep_for(1500ms);
  const std::uint64_t commits_before = stats.commits.load();
  ASSERT_NO_FATAL_FAILURE(feed(channels, run_id, cycle, 1ms));
  ASSERT_NO_FATAL_FAILURE(until_committed(recorder, cycle));
  EXPECT_EQ(stats.commits.load(), commits_before + 1);
  EXPECT_LT(stats.last_exposure_us.load(), 1'000'000) << "the idle spell was counted as exposure [us]";
  recorder.stop();
}

}  // namespace
}  // namespace rig::service
