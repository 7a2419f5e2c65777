// A long `rig import` shares the archive with rigd's recorder: it must never hold the write
// lock long enough to fault a running cut (SQLite's busy timeout is 5 s; the recorder commits
// every 50 ms and its ring holds about a second).
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <optional>
#include <thread>

#include "archive.hpp"
#include "long_run.hpp"
#include "test_paths.hpp"

namespace rig::archive {
namespace {

using Clock = std::chrono::steady_clock;

model::RunData long_run(std::size_t samples) {
  return testing::long_run(samples, 1e-4);
}  // [s] apart

TEST(ArchiveImport, ALongImportNeverHoldsOffTheRecordersCommitsForLongerThanOneChunk) {
  testing::ScratchDir dir("archive-import-lock");
  const std::string path = dir.file("a.sqlite");
  Archive recorder(path);
  const std::int64_t cut = recorder.create_run(NewRun{});
  recorder.mark_started(cut);
  const model::RunData big = long_run(400'000);

  std::atomic<bool> importing{true};
  std::int64_t imported = 0;
  Clock::duration import_took{};
  std::thread importer([&] {
    Archive cli(path);
    const auto start = Clock::now();
    imported = cli.import_run(big);
    import_took = Clock::now() - start;
    importing.store(false);
  });
  // The recorder's rhythm: a short write transaction every few ms, as long as the import runs.
  Clock::duration longest_commit{};
  std::uint64_t cycle = 0;
  int commits = 0;
  while (importing.load()) {
    const auto start = Clock::now();
    recorder.begin();
    rt::Sample s;
    s.run_id = cut;
    s.cycle = cycle++;
    recorder.append_sample(s);
    recorder.commit();  // throws on SQLITE_BUSY: the cut would fault
    longest_commit = std::max(longest_commit, Clock::now() - start);
    ++commits;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  importer.join();
  const double import_ms = std::chrono::duration<double, std::milli>(import_took).count();
  const double longest_ms = std::chrono::duration<double, std::milli>(longest_commit).count();
  std::printf("import %.0f ms, %d recorder commits meanwhile, longest %.1f ms\n", import_ms,
              commits, longest_ms);
  ASSERT_GT(import_ms, 200.0) << "the import is too short to tell";
  // One chunk (20 ms) and a poll, not the whole import: a single-transaction import holds
  // every commit off until it ends.
  EXPECT_LT(longest_ms, import_ms / 4) << "the recorder waited for most of the import";
  EXPECT_GT(commits, 10);
  const auto row = recorder.find_run(imported);
  ASSERT_TRUE(row.has_value());
  EXPECT_EQ(row->outcome, "imported");
  EXPECT_EQ(row->samples, 400'000);
  EXPECT_EQ(recorder.find_run(cut)->samples, commits);
  for (const auto& [key, value] : recorder.run_meta(imported))
    EXPECT_NE(key, "import_process") << value;
}

// A `rig import` killed half-way leaves a run 'importing' that nobody will finish: the next
// rigd start or `rig import` removes it and names its file (the file still holds every
// sample), but never while the importing process still runs.
TEST(ArchiveImport, AHalfImportWhoseProcessWasKilledIsRemovedAndNamedButARunningOneIsLeftAlone) {
  testing::ScratchDir dir("archive-import-killed");
  const std::string path = dir.file("a.sqlite");
  { Archive create(path); }
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    Archive cli(path);
    cli.import_run(long_run(5'000'000));  // minutes: killed long before the end
    _exit(0);
  }
  Archive rigd(path);
  std::optional<RunRow> half;
  for (int i = 0; i < 3000 && !(half && half->samples > 0); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    const auto runs = rigd.list_runs();
    if (!runs.empty()) half = runs.back();
  }
  ASSERT_TRUE(half && half->outcome == "importing" && half->samples > 0)
      << "the import never started writing samples";
  EXPECT_TRUE(rigd.remove_abandoned_imports().empty()) << "an import still running was removed";
  EXPECT_TRUE(rigd.find_run(half->id).has_value());
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(rigd.remove_abandoned_imports(), std::vector<std::string>{"long.csv"});
  EXPECT_FALSE(rigd.find_run(half->id).has_value());
  EXPECT_TRUE(rigd.list_runs().empty());
  EXPECT_TRUE(rigd.remove_abandoned_imports().empty());
}

}  // namespace
}  // namespace rig::archive
