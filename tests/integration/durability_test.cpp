// Durability: rigd is killed with SIGKILL at a random moment of 50 runs (arming, approach,
// cutting; two rigs with their own archives, 25 runs each, side by side); afterwards each
// archive opens, passes SQLite's integrity check, every run is consistent (contiguous samples,
// times rising, outcome set at the next start) and at most 100 ms of samples are missing at the end
// of any run. Prints the worst case (docs/faults.md quotes it). Release tree, label durability.
#include <gtest/gtest.h>
#include <signal.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <random>
#include <thread>

#include "archive.hpp"
#include "rig_processes.hpp"
#include "sqlite_handle.hpp"

namespace rig {
namespace {

using nlohmann::json;
using testing::RigProcesses;
using testing::ScratchDir;

struct Kill {
  std::int64_t run_id = 0;
  double cycle_at_kill = 0;  // the loop's cycle when the signal was sent (extrapolated at 1 kHz)
  std::string state;
  std::string fault;    // the fault that ended the run before the kill, if it did
  std::string commits;  // the recorder's commit tally just before the kill (for a failure)
};

// Runs that faulted by accident (the DAQ link starved on this shared VM) before the kill;
// the subject here is the archive, so the run is retried and the count printed, not hidden.
std::atomic<int> accidental_faults{0};

// Starts a run and, unless it is to be killed while arming, waits until it cuts. Returns the
// run id, 0 if the run faulted first (its reason in `why`), -1 if it was refused.
std::int64_t start_run(RigProcesses& rig, bool wait_for_cutting, std::string& why) {
  const auto reply =
      rig.api().post("/api/run", R"({"eye_id":"D","iop_mmHg":15,"velocity_mm_s":4,"depth_mm":8})");
  EXPECT_EQ(reply.status, 200) << reply.body;
  if (reply.status != 200) return -1;
  const std::int64_t id = json::parse(reply.body)["run_id"];
  if (!wait_for_cutting) return id;
  json last;
  const bool settled = rig.wait(
      [&](const json& s) {
        last = s;
        return s["state"] == "Cutting" || s["state"] == "Fault";
      },
      30);
  if (settled && last["state"] == "Cutting") return id;
  why = last.dump();
  if (!settled) ADD_FAILURE() << "run " << id << " never reached Cutting: " << why;
  return settled ? 0 : id;
}

// One run: home, tare, start, SIGKILL at a random moment; what the loop had done by then.
Kill run_and_kill(RigProcesses& rig, std::mt19937& rng, int i) {
  static std::uniform_int_distribution<int> delay_ms(0, 1500);
  std::string why;
  Kill k;
  for (int attempt = 0; attempt < 3; ++attempt) {
    // The subject is the archive, not the link: a reset and a retry if this shared VM
    // starved the DAQ link while homing or arming (counted in accidental_faults).
    if (!rig.prepare(why)) {
      ++accidental_faults;
      rig.api().post("/api/reset");
      if (!rig.prepare(why)) ADD_FAILURE() << "run " << i << ": " << why;
    }
    // Every fifth kill lands while arming (IOP settling, approach), the others while cutting.
    k.run_id = start_run(rig, i % 5 != 0, why);
    if (k.run_id != 0) break;
    ++accidental_faults;
    std::printf("DURABILITY | run %d faulted before the kill, retried: %s\n", i, why.c_str());
    rig.api().post("/api/reset");
  }
  if (k.run_id <= 0) {
    ADD_FAILURE() << "run " << i << " never started cutting: " << why;
    k.run_id = 0;  // still killed below: the next round restarts rigd
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms(rng)));
  const json before = rig.status();
  const auto read_at = std::chrono::steady_clock::now();
  ::kill(rig.rigd().pid(), SIGKILL);
  const double since_read_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - read_at).count();
  k.cycle_at_kill = before["loop"]["cycles"].get<double>() + since_read_s * 1000.0;
  k.state = before["state"];
  k.commits = before.value("archive_commits", json::object()).dump();
  if (k.state == "Fault") {
    // The run ended at its fault, before the kill: the cycles since are not samples it
    // lost. Its archive is still checked; the accidental fault is counted and printed.
    k.fault = before.dump();
    ++accidental_faults;
    std::printf("DURABILITY | run %d faulted after it began cutting, before the kill: %s\n", i,
                k.fault.c_str());
  }
  return k;
}

// Checks one run in the archive; returns the samples lost at its end [ms], -1 if it had none.
double check_run(archive::Database& db, const Kill& k) {
  auto row = db.prepare("SELECT outcome FROM runs WHERE id = ?");
  row.bind(1, k.run_id);
  if (!row.step()) {
    ADD_FAILURE() << "run " << k.run_id << " missing";
    return -1.0;
  }
  EXPECT_NE(row.text(0), "recording") << "run " << k.run_id << " still open after the restart";
  auto q = db.prepare("SELECT COUNT(*), MIN(idx), MAX(idx) FROM samples WHERE run_id = ?");
  q.bind(1, k.run_id);
  q.step();
  const std::int64_t count = q.integer(0);
  if (count == 0) return -1.0;  // killed before cutting started: nothing to lose
  EXPECT_EQ(q.integer(2) - q.integer(1) + 1, count) << "a gap in run " << k.run_id;
  auto order = db.prepare(
      "SELECT COUNT(*) FROM samples a JOIN samples b ON a.run_id = b.run_id AND b.idx = a.idx + 1 "
      "WHERE a.run_id = ? AND b.t_s <= a.t_s");
  order.bind(1, k.run_id);
  order.step();
  EXPECT_EQ(order.integer(0), 0) << "time goes backwards in run " << k.run_id;
  if (!k.fault.empty()) return -1.0;  // ended by its fault, not by the kill: no loss to judge
  const double missing_ms =
      (k.cycle_at_kill - static_cast<double>(q.integer(2) + 1)) * 1.0;  // 1 ms per cycle
  EXPECT_LE(missing_ms, 100.0) << "run " << k.run_id << " (" << k.state << ") lost " << missing_ms
                               << " ms; the recorder before the kill: " << k.commits;
  return missing_ms;
}

// 25 runs on one rig (rig-sim + rigd + archive); two rigs run side by side to halve the time.
std::vector<Kill> kill_runs(const ScratchDir& dir, unsigned seed, std::string& archive_path) {
  // The eye close to the home switch and homing at 6 mm/s: re-homing after each restart
  // (rigd always starts unhomed) takes a third of the time of the standard geometry.
  RigProcesses rig(dir, {"--surface-mm", "12"},
                   {"motion.surface_mm=12", "motion.park_mm=10", "motion.homing_velocity_mm_s=6",
                    "motion.retract_velocity_mm_s=6"});
  std::mt19937 rng(seed);
  std::vector<Kill> kills;
  // 25 kills of runs that had not faulted by accident first; a run that faulted before its
  // kill (the DAQ link starved on this shared VM) is still checked, and one more is run in
  // its place, at most 10 times (each is counted and printed).
  int clean_kills = 0;
  for (int i = 0; clean_kills < 25 && i < 35; ++i) {
    if (i > 0) rig.start_rigd();
    kills.push_back(run_and_kill(rig, rng, i));
    if (kills.back().fault.empty()) ++clean_kills;
  }
  rig.start_rigd();  // marks the last run interrupted
  archive_path = rig.archive_path();
  return kills;
}

TEST(Durability, FiftyKillsAtRandomMomentsLeaveAConsistentArchiveMissingAtMost100msPerRun) {
  ScratchDir dir_a("durability-a"), dir_b("durability-b");
  std::vector<Kill> kills_a, kills_b;
  std::string archive_a, archive_b;
  std::thread second([&] {
    try {
      kills_b = kill_runs(dir_b, 7, archive_b);
    } catch (const std::exception& e) {
      ADD_FAILURE() << "second rig: " << e.what();
    }
  });
  kills_a = kill_runs(dir_a, 20261122, archive_a);
  second.join();
  double worst_ms = 0.0;
  int runs_with_samples = 0;
  for (const auto& [path, kills] : {std::pair{archive_a, kills_a}, std::pair{archive_b, kills_b}}) {
    ASSERT_FALSE(path.empty());
    archive::Database db(path, true);
    auto integrity = db.prepare("PRAGMA integrity_check");
    ASSERT_TRUE(integrity.step());
    EXPECT_EQ(integrity.text(0), "ok") << path;
    for (const Kill& k : kills) {
      if (k.run_id == 0) continue;  // already a failure above
      const double lost = check_run(db, k);
      if (lost < 0) continue;
      ++runs_with_samples;
      worst_ms = std::max(worst_ms, lost);
    }
  }
  const auto clean = [](const std::vector<Kill>& kills) {
    return std::count_if(kills.begin(), kills.end(), [](const Kill& k) { return k.fault.empty(); });
  };
  EXPECT_EQ(clean(kills_a) + clean(kills_b), 50)
      << "too many runs faulted by accident before their kill";
  EXPECT_GE(runs_with_samples, 35) << "too few kills landed during cutting to mean anything";
  std::printf(
      "DURABILITY | 50 kills on 2 rigs, %d runs with samples | worst loss %.1f ms of samples "
      "(limit 100 ms)"
      " | %d accidental faults before a kill (retried)\n",
      runs_with_samples, worst_ms, accidental_faults.load());
}

}  // namespace
}  // namespace rig
