// Issue 16's "done when", end to end: three rigds (each with its rig-sim and its own SQLite
// archive) point at one throwaway PostgreSQL 15 with [lab_archive] on, cut side by side, and
// one `rig` command lists and diagnoses all their runs together from the lab archive.
// Release tree (label lab): six real-time processes do not fit a sanitized 2-core machine.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <atomic>
#include <cstdio>
#include <memory>
#include <thread>

#include "archive.hpp"
#include "command.hpp"
#include "pg_test_server.hpp"
#include "rig_processes.hpp"

namespace rig::lab_archive {
namespace {

using nlohmann::json;

constexpr int kCutsPerRig = 2;
const std::string kCut =
    R"({"eye_id":"E3R","iop_mmHg":15,"velocity_mm_s":4,"depth_mm":8,"meta":{"eye_lot":"LOT-3R"}})";

// Accidental faults (a starved DAQ link on a loaded machine) are retried: the subject is the
// lab archive. Counted and printed, never hidden.
std::atomic<int> accidental_faults{0};

// One completed cut: home, tare, run, parked again (Done). Returns false with the status in `why`.
bool cut_once(const testing::RigProcesses& rig, std::string& why) {
  constexpr int kAttempts = 5;  // measured: 6 retries over 6 cuts beside a running ASan tier
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    if (attempt > 0) {
      ++accidental_faults;
      std::printf("THREE RIGDS | accidental fault, retried: %s\n", why.c_str());
      rig.api().post("/api/reset");
    }
    if (!rig.prepare(why)) continue;
    if (rig.api().post("/api/run", kCut).status != 200)
      return why = "run refused: " + rig.status().dump(), false;
    json last;
    const bool settled = rig.wait(
        [&](const json& s) {
          last = s;
          return s["state"] == "Fault" || s["state"] == "Done";  // Done: cut, retracted, parked
        },
        60);
    why = last.dump();
    if (!settled) return false;
    if (last["state"] == "Done") return true;
  }
  return false;
}

bool drained(const json& s) {
  const json& lab = s["lab_archive"];
  return lab["connected"] == true && lab["backlog_known"] == true && lab["backlog_samples"] == 0 &&
         lab["backlog_runs"] == 0;
}

// Samples of the completed runs in the rigs' own archives.
std::int64_t completed_samples(const std::vector<std::unique_ptr<testing::RigProcesses>>& rigs) {
  std::int64_t samples = 0;
  for (const auto& rig : rigs) {
    archive::Archive local(rig->archive_path(), true);
    for (const auto& run : local.list_runs()) {
      if (run.outcome == "completed") samples += run.samples;
    }
  }
  return samples;
}

TEST(LabArchiveThreeRigds, ThreeRigdsCutIntoOnePostgresqlAndOneCommandDiagnosesAllTheirRuns) {
  testing::PgTestServer server;
  const std::array<std::string, 3> names = {"rig-a", "rig-b", "rig-c"};
  std::vector<std::unique_ptr<testing::ScratchDir>> dirs;
  std::vector<std::unique_ptr<testing::RigProcesses>> rigs;
  for (const std::string& name : names) {
    dirs.push_back(std::make_unique<testing::ScratchDir>("lab-3-" + name));
    // The eye close to the home switch (as in the durability test): short homing and cuts.
    rigs.push_back(std::make_unique<testing::RigProcesses>(
        *dirs.back(), std::vector<std::string>{"--surface-mm", "12"},
        std::vector<std::string>{
            "motion.surface_mm=12", "motion.park_mm=10", "motion.homing_velocity_mm_s=6",
            "motion.retract_velocity_mm_s=6", "lab_archive.enabled=true",
            "lab_archive.conninfo=\"" + server.conninfo() + "\"",
            "lab_archive.rig_id=\"" + name + "\"", "lab_archive.sslmode=\"disable\""}));
  }
  std::array<std::string, 3> failures;
  std::vector<std::thread> cutting;
  for (std::size_t i = 0; i < rigs.size(); ++i) {
    cutting.emplace_back([&, i] {
      std::string why;
      for (int c = 0; c < kCutsPerRig && failures[i].empty(); ++c) {
        if (!cut_once(*rigs[i], why))
          failures[i] = names[i] + " cut " + std::to_string(c) + ": " + why;
      }
    });
  }
  for (auto& t : cutting) t.join();
  for (const std::string& f : failures) ASSERT_TRUE(f.empty()) << f;
  for (std::size_t i = 0; i < rigs.size(); ++i) {
    ASSERT_TRUE(rigs[i]->wait(drained, 60)) << names[i] << ": " << rigs[i]->status().dump();
  }

  // The lab holds every completed run of every rig, sample for sample.
  const std::int64_t local_samples = completed_samples(rigs);
  EXPECT_EQ(
      server.query("SELECT count(*) FROM runs WHERE outcome = 'completed' AND eye_lot = 'LOT-3R'"),
      std::to_string(3 * kCutsPerRig));
  EXPECT_EQ(server.query("SELECT count(*) FROM samples s JOIN runs r USING (run_uuid) WHERE "
                         "r.outcome = 'completed'"),
            std::to_string(local_samples));

  const std::string pg = "'pg:" + server.conninfo() + "'";
  const auto rig_cli = [](const std::string& args) {
    return testing::run_command(testing::bin("rig") + " " + args);
  };
  const auto listed = rig_cli("--format json runs " + pg + " --eye-lot LOT-3R outcome=completed");
  ASSERT_EQ(listed.exit_code, 0) << listed.output;
  EXPECT_EQ(json::parse(listed.output)["runs"].size(), 3U * kCutsPerRig) << listed.output;
  const auto of_b = rig_cli("--format json runs " + pg + " --rig rig-b outcome=completed");
  EXPECT_EQ(json::parse(of_b.output)["runs"].size(), static_cast<std::size_t>(kCutsPerRig))
      << of_b.output;
  // One command over all three rigs' runs.
  const auto compared =
      rig_cli("--format json model compare " + pg + " --eye-lot LOT-3R outcome=completed");
  ASSERT_EQ(compared.exit_code, 0) << compared.output;
  const json comparison = json::parse(compared.output.substr(compared.output.find('{')));
  EXPECT_EQ(comparison["runs"].size(), 3U * kCutsPerRig) << compared.output;
  const auto diagnosed =
      rig_cli("--format json model diagnose " + pg + " --eye-lot LOT-3R outcome=completed");
  ASSERT_EQ(diagnosed.exit_code, 0) << diagnosed.output;
  const json diagnosis = json::parse(diagnosed.output.substr(diagnosed.output.find('{')));
  EXPECT_TRUE(diagnosis.contains("verdict")) << diagnosed.output;
  std::printf(
      "THREE RIGDS | %d completed runs, %lld samples in the lab archive | %d accidental faults "
      "(retried) | verdict: %s\n",
      3 * kCutsPerRig, static_cast<long long>(local_samples), accidental_faults.load(),
      diagnosis.value("verdict", json()).dump().c_str());
}

}  // namespace
}  // namespace rig::lab_archive
