// rigd's store and forward end to end: rig-sim + rigd with [lab_archive] on, a throwaway
// PostgreSQL 15 behind a proxy the test cuts. The lab is cut off while a run records, rigd
// is killed with a backlog, the network comes back, rigd restarts: every sample of the run
// reaches the lab once. Real-time processes: label e2e, SERIAL.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <signal.h>

#include "archive.hpp"
#include "command.hpp"
#include "lab_run_reader.hpp"
#include "local_run_writer.hpp"
#include "pg_test_server.hpp"
#include "rig_processes.hpp"
#include "tcp_cut_proxy.hpp"

namespace rig::lab_archive {
namespace {

using nlohmann::json;

// 0.5 mm/s, the rig's slowest: 16 s into the eye, so the kill below comes mid-run even when a
// loaded machine is slow to reach it (at 2 mm/s the run completed first under ./rig stress).
const std::string kRun =
    R"({"eye_id":"E07","iop_mmHg":15,"velocity_mm_s":0.5,"depth_mm":8,"meta":{"eye_lot":"L7"}})";

json lab_status(const testing::RigProcesses& rig) {
  return rig.status().value("lab_archive", json::object());
}

TEST(LabArchiveRigd, ARigdKilledWithABacklogDuringANetworkCutResumesAndTheLabGetsEverySampleOnce) {
  testing::ScratchDir dir("lab-rigd");
  testing::PgTestServer server;
  testing::TcpCutProxy proxy(server.port());
  testing::RigProcesses rig(
      dir, {},
      {"lab_archive.enabled=true", "lab_archive.conninfo=\"" + server.conninfo(proxy.port()) + "\"",
       "lab_archive.rig_id=\"rig-e2e\"", "lab_archive.sslmode=\"disable\"",
       "lab_archive.retry_max_ms=500"});
  ASSERT_TRUE(rig.wait([](const json& s) { return s["lab_archive"]["connected"] == true; }, 20))
      << rig.status().dump();
  std::string why;
  ASSERT_TRUE(rig.prepare(why)) << why;
  proxy.cut();
  ASSERT_EQ(rig.api().post("/api/run", kRun).status, 200);
  ASSERT_TRUE(rig.wait(
      [](const json& s) { return s["state"] == "Cutting" && s["position_mm"] > 21.0; }, 30))
      << rig.status().dump();
  ASSERT_TRUE(rig.wait([](const json& s) { return s["lab_archive"]["backlog_samples"] > 500; }, 10))
      << rig.status().dump();
  EXPECT_EQ(lab_status(rig)["connected"], false);
  const auto status_line =
      testing::run_command(testing::bin("rig") + " --api " + rig.url() + " status");
  EXPECT_NE(status_line.output.find("NOT CONNECTED as rig-e2e, backlog 1 runs"), std::string::npos)
      << status_line.output;
  ASSERT_EQ(rig.status()["state"], "Cutting")
      << "the run ended before the kill: this test needs it mid-run";
  kill(rig.rigd().pid(), SIGKILL);
  usleep(300000);
  proxy.restore();
  rig.start_rigd();  // marks the run interrupted, then ships what the lab is missing
  ASSERT_TRUE(rig.wait(
      [](const json& s) {
        const json& lab = s["lab_archive"];
        return lab["connected"] == true && lab["backlog_known"] == true &&
               lab["backlog_samples"] == 0 && lab["backlog_runs"] == 0;
      },
      30))
      << rig.status().dump();
  archive::Archive local(rig.archive_path(), true);
  const auto run = local.find_run(1);
  ASSERT_TRUE(run.has_value());
  EXPECT_EQ(run->outcome, "interrupted");
  EXPECT_EQ(server.query("SELECT count(*) || ' ' || count(DISTINCT idx) FROM samples"),
            std::to_string(run->samples) + " " + std::to_string(run->samples));
  EXPECT_EQ(server.query("SELECT rig_id || ' ' || outcome || ' ' || eye_lot FROM runs"),
            "rig-e2e interrupted L7");
  LabRunReader reader(server.conninfo());
  const auto rows = reader.list_runs({});
  ASSERT_EQ(rows.size(), 1U);
  EXPECT_EQ(testing::run_checksum(reader.load_run(rows[0].uuid)),
            testing::run_checksum(local.load_run(1)));

  // The page's run picker reads the lab archive through rigd: the same run, sample for sample,
  // as the rig's own replay of it.
  const json listed =
      json::parse(rig.api().get("/api/lab-archive/runs?rig=rig-e2e&eye_lot=L7").body);
  ASSERT_EQ(listed["runs"].size(), 1U) << listed.dump();
  EXPECT_EQ(listed["runs"][0]["run_uuid"], rows[0].uuid);
  EXPECT_EQ(listed["runs"][0]["samples"], run->samples);
  EXPECT_EQ(json::parse(rig.api().get("/api/lab-archive/runs?eye_lot=OTHER").body)["runs"].size(),
            0U);
  const json remote = json::parse(
      rig.api().get("/api/lab-archive/runs/" + rows[0].uuid + "/stream?limit=1000000").body);
  const json own = json::parse(rig.api().get("/api/runs/1/stream?limit=1000000").body);
  EXPECT_EQ(remote["cycle"], own["cycle"]);
  EXPECT_EQ(remote["force_N"], own["force_N"]);
  EXPECT_EQ(remote["x_mm"], own["x_mm"]);
  EXPECT_EQ(remote["phase"], own["phase"]);
  EXPECT_EQ(remote["model_N"], own["model_N"]);
  EXPECT_EQ(remote["events"].size(), own["events"].size());
  EXPECT_EQ(remote["rig_id"], "rig-e2e");
  EXPECT_EQ(rig.api().get("/api/lab-archive/runs/not-a-uuid/stream").status, 400);
  EXPECT_EQ(
      rig.api().get("/api/lab-archive/runs/00000000-0000-0000-0000-000000000000/stream").status,
      404);
  EXPECT_EQ(rig.api().get("/api/lab-archive/runs?rig").status, 400);
}

}  // namespace
}  // namespace rig::lab_archive
