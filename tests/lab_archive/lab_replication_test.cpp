// Store and forward from a rig's SQLite archive to a real PostgreSQL 15 (throwaway server):
// exact copies, in-progress runs shipped in pieces, server stops, network cuts. A run is
// "exact" when its row counts match and the checksum of every value read back matches.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <chrono>
#include <fstream>
#include <limits>
#include <thread>

#include "lab_replicator.hpp"
#include "lab_run_reader.hpp"
#include "lab_schema.hpp"
#include "local_run_writer.hpp"
#include "pg_copy_in.hpp"
#include "pg_test_server.hpp"
#include "run_csv.hpp"
#include "run_uuid.hpp"
#include "tcp_cut_proxy.hpp"
#include "test_paths.hpp"

namespace rig::lab_archive {
namespace {

using Clock = std::chrono::steady_clock;

std::string uuid_of(archive::Archive& local, const std::string& rig, std::int64_t run_id) {
  archive::Database db(local.path(), true);
  archive::Statement q = db.prepare("SELECT created_at FROM runs WHERE id = ?");
  q.bind(1, run_id);
  EXPECT_TRUE(q.step());
  return lab_run_uuid(rig, run_id, q.text(0));
}

// Every sample, event and value of the local run is on the server once.
void expect_exact_copy(const testing::PgTestServer& server, archive::Archive& local,
                       const std::string& rig, std::int64_t run_id) {
  const std::string uuid = uuid_of(local, rig, run_id);
  const auto row = local.find_run(run_id);
  ASSERT_TRUE(row.has_value());
  EXPECT_EQ(
      server.query("SELECT count(*) || ' ' || count(DISTINCT idx) FROM samples WHERE run_uuid = '" +
                   uuid + "'"),
      std::to_string(row->samples) + " " + std::to_string(row->samples));
  EXPECT_EQ(server.query("SELECT count(*) FROM events WHERE run_uuid = '" + uuid + "'"),
            std::to_string(local.run_events(run_id).size()));
  LabRunReader reader(server.conninfo());
  const model::RunData remote = reader.load_run(uuid);
  const model::RunData original = local.load_run(run_id);
  EXPECT_EQ(remote.size(), original.size());
  EXPECT_EQ(testing::run_checksum(remote), testing::run_checksum(original));
  for (const auto& [key, value] : original.meta) EXPECT_EQ(remote.text(key), value) << key;
  EXPECT_EQ(remote.text("rig_id"), rig);
}

// The first status that satisfies `wanted` within `seconds`, else the last one seen.
template <typename Predicate>
ReplicatorStatus status_once(LabReplicator& replicator, double seconds, Predicate wanted) {
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  ReplicatorStatus s = replicator.status();
  while (!wanted(s) && Clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    s = replicator.status();
  }
  return s;
}

// Waits until the replicator has shipped every sample and every run's end.
bool drained(LabReplicator& replicator, double seconds) {
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < until) {
    const ReplicatorStatus s = replicator.status();
    if (s.connected && s.backlog.known && s.backlog.samples == 0 && s.backlog.runs == 0)
      return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

LabArchiveSettings settings_for(const std::string& conninfo, const std::string& rig) {
  LabArchiveSettings s;
  s.enabled = true;
  s.conninfo = conninfo;
  s.rig_id = rig;
  s.interval_ms = 50;
  s.batch_samples = 4000;
  s.retry_max_ms = 300;
  s.sslmode = "disable";
  return s;
}

// A rig's local archive with a run writer, and a throwaway lab server.
class LabReplication : public ::testing::Test {
 protected:
  // A connection to the lab archive with the current schema.
  PgConnection lab() {
    PgConnection db(server.conninfo());
    create_or_migrate_lab_schema(db);
    return db;
  }
  testing::ScratchDir dir{"lab-replication"};
  testing::PgTestServer server;
  archive::Archive local{dir.file("a.sqlite")};
  testing::LocalRunWriter writer{local};
};

TEST_F(LabReplication, AFinishedRunReplicatesExactlyWithItsEventsFramesAndMetadata) {
  const std::int64_t id = writer.start("E07", "L7");
  for (int batch = 0; batch < 5; ++batch) writer.append(id, 1000);
  local.add_frame({id, 0, 1500, 111, 222, 0, 4096, 64, 48, "frames/run-1.bin"});
  writer.finish(id);
  PgConnection db = lab();
  RunShipper shipper(local.path(), "rig-a", "test");
  EXPECT_EQ(shipper.ship_pass(db, 100000), 5000);
  expect_exact_copy(server, local, "rig-a", id);
  EXPECT_EQ(server.query("SELECT frame_no || ' ' || sample_index || ' ' || file FROM frames"),
            "0 1500 frames/run-1.bin");
  EXPECT_EQ(server.query("SELECT eye_lot || ' ' || outcome || ' ' || notes FROM runs"),
            "L7 completed tab\tand newline\nand backslash \\ in notes");
  EXPECT_EQ(shipper.ship_pass(db, 100000), 0);  // nothing left, nothing sent twice
  EXPECT_EQ(shipper.backlog().samples, 0);
  EXPECT_EQ(shipper.backlog().runs, 0);
}

TEST_F(LabReplication, AnImportedRunKeepsItsOwnChannels) {
  model::RunData csv;
  csv.source = "elsewhere.csv";
  csv.meta = {{"eye_id", "P3"}, {"velocity_mm_s", "1.5"}};
  for (int i = 0; i < 300; ++i) {
    csv.t_s.push_back(i * 1e-3);
    csv.x_mm.push_back(i * 1.5e-3);
    csv.force_N.push_back(0.01 * i + 1e-3 / 3.0);
  }
  csv.channels = {{"temperature_C", std::vector<double>(300, 36.6)},
                  {"strain_u", std::vector<double>(300, -1.0 / 7.0)}};
  const std::int64_t id = local.import_run(csv);
  PgConnection db = lab();
  RunShipper shipper(local.path(), "rig-b", "test");
  shipper.ship_pass(db, 100000);
  expect_exact_copy(server, local, "rig-b", id);
  EXPECT_EQ(server.query("SELECT string_agg(name, ',' ORDER BY seq) FROM channels"),
            "temperature_C,strain_u");
}

TEST_F(LabReplication, ARunInProgressShipsInPiecesAndEndsComplete) {
  PgConnection db = lab();
  RunShipper shipper(local.path(), "rig-a", "test");
  const std::int64_t id = writer.start("E08", "L7");
  for (int batch = 0; batch < 4; ++batch) {
    writer.append(id, 700);
    EXPECT_EQ(shipper.backlog().samples, 700);
    EXPECT_EQ(shipper.ship_pass(db, 500), 500);  // the budget caps one pass
    EXPECT_EQ(shipper.ship_pass(db, 500), 200);
    EXPECT_EQ(server.query("SELECT outcome FROM runs"), "recording");
  }
  writer.finish(id);
  EXPECT_EQ(shipper.backlog().runs, 1);  // the outcome is not on the server yet
  shipper.ship_pass(db, 500);
  EXPECT_EQ(shipper.backlog().runs, 0);
  expect_exact_copy(server, local, "rig-a", id);
  EXPECT_EQ(server.query("SELECT outcome FROM runs"), "completed");
}

TEST_F(LabReplication, TwoShippersOfOneRigNeverSendASampleTwice) {
  PgConnection db_a = lab(), db_b = lab();
  RunShipper a(local.path(), "rig-a", "test"),
      b(local.path(), "rig-a", "test");  // e.g. rigd and a manual push
  const std::int64_t id = writer.start("E11", "L9");
  writer.append(id, 1000);
  EXPECT_EQ(a.ship_pass(db_a, 600), 600);
  EXPECT_EQ(b.ship_pass(db_b, 100000),
            400);  // b's first look at the server is under the run's lock
  writer.append(id, 100);
  EXPECT_EQ(a.ship_pass(db_a, 100000),
            100);  // a's cached watermark is stale; the locked one is not
  EXPECT_EQ(b.ship_pass(db_b, 100000), 0);
  EXPECT_EQ(server.query("SELECT count(*) || ' ' || count(DISTINCT idx) FROM samples"),
            "1100 1100");
}

TEST_F(LabReplication, AServerStoppedMidRunAndRestartedLosesNothingAndDuplicatesNothing) {
  LabReplicator replicator(settings_for(server.conninfo(), "rig-a"), local.path(), "test");
  replicator.start();
  const std::int64_t id = writer.start("E09", "L8");
  for (int batch = 0; batch < 10; ++batch) {
    writer.append(id, 500);  // a cut at 1 kHz: 0.5 s per batch, committed as the recorder does
    if (batch == 3) server.stop("immediate");  // like a crash: WAL replay at the restart
    if (batch == 6) server.start();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  writer.finish(id);
  ASSERT_TRUE(drained(replicator, 20)) << replicator.status().last_error;
  expect_exact_copy(server, local, "rig-a", id);
}

TEST_F(LabReplication, TheBacklogGrowsWhileTheNetworkIsCutAndDrainsAfter) {
  testing::TcpCutProxy proxy(server.port());
  LabReplicator replicator(settings_for(server.conninfo(proxy.port()), "rig-a"), local.path(),
                           "test");
  replicator.start();
  const std::int64_t id = writer.start("E10", "L8");
  writer.append(id, 1000);
  // A status counted before the append also reads "nothing behind": wait for the 1000 shipped.
  const ReplicatorStatus before = status_once(replicator, 15, [](const ReplicatorStatus& s) {
    return s.connected && s.samples_shipped == 1000 && s.backlog.known && s.backlog.samples == 0;
  });
  ASSERT_EQ(before.samples_shipped, 1000) << before.last_error;
  EXPECT_EQ(before.backlog.runs, 1);  // still recording
  proxy.cut();
  std::int64_t seen_during_cut = 0;
  for (int batch = 0; batch < 4; ++batch) {
    writer.append(id, 1000);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const ReplicatorStatus s = replicator.status();
    EXPECT_GE(s.backlog.samples,
              seen_during_cut);  // it grows (or holds) while the lab is out of reach
    seen_during_cut = s.backlog.samples;
  }
  // The replicator counts its backlog on each retry (at most retry_max_ms = 300 ms apart, later
  // on a loaded machine): wait for the count that includes the last batch.
  const ReplicatorStatus during = status_once(
      replicator, 10, [](const ReplicatorStatus& s) { return s.backlog.samples >= 4000; });
  EXPECT_FALSE(during.connected);
  EXPECT_EQ(during.backlog.samples, 4000);
  EXPECT_NE(during.last_error.find("lab archive"), std::string::npos) << during.last_error;
  proxy.restore();
  writer.finish(id);
  ASSERT_TRUE(drained(replicator, 20)) << replicator.status().last_error;
  expect_exact_copy(server, local, "rig-a", id);
}

TEST_F(LabReplication, ExtremeValuesArriveBitForBitInTheRunsMonthPartition) {
  const std::int64_t id = writer.start("E12", "L9");
  const double extremes[] = {std::numeric_limits<double>::infinity(),
                             -std::numeric_limits<double>::infinity(),
                             std::numeric_limits<double>::denorm_min(),
                             std::numeric_limits<double>::max(),
                             std::numeric_limits<double>::lowest(),
                             0.1 + 0.2,
                             -1.0 / 3.0,
                             1e-300};
  local.begin();
  for (std::uint64_t i = 0; i < 64; ++i) {
    rt::Sample s;
    s.run_id = id;
    s.cycle = 7 + i * 1000003;  // far apart: the index is not a small counter
    s.t_s = 1e9 + static_cast<double>(i) * 1e-3;
    s.position_mm = extremes[i % 8];
    s.force_N = extremes[(i + 3) % 8];
    s.iop_mmHg = extremes[(i + 5) % 8];
    s.velocity_mm_s = extremes[(i + 1) % 8];
    s.motor_volts = extremes[(i + 6) % 8];
    s.state = static_cast<rt::RunState>(i % 8);
    s.io_ok = static_cast<std::uint8_t>(i % 2);
    local.append_sample(s);
  }
  local.commit();
  writer.finish(id);
  PgConnection db = lab();
  RunShipper shipper(local.path(), "rig-a", "test");
  EXPECT_EQ(shipper.ship_pass(db, 100000), 64);
  expect_exact_copy(server, local, "rig-a", id);
  EXPECT_EQ(server.query("SELECT count(*) FROM samples s JOIN runs r USING (run_uuid) WHERE "
                         "s.run_created_at = r.created_at"
                         " AND s.tableoid::regclass::text = 'samples_' || to_char(r.created_at AT "
                         "TIME ZONE 'UTC', 'YYYY_MM')"),
            "64");
  EXPECT_EQ(server.query("SELECT count(*) FILTER (WHERE force_n = 'Infinity') || ' ' || max(idx) "
                         "|| ' ' || sum(io_ok)"
                         " || ' ' || max(state) FROM samples"),
            "8 63000196 32 7");
}

// The samples of one pass go to the server in pieces (about 1 MiB each): a batch the server
// refuses after it has taken some pieces leaves nothing behind, and the next pass sends it all.
TEST_F(LabReplication, ABatchRefusedHalfwayIsSentAgainWholeAndOnlyOnce) {
  const std::int64_t id = writer.start("E13", "L9");
  for (int batch = 0; batch < 4; ++batch)
    writer.append(id, 10000);  // cycles 1000..40999, about 6 MB binary
  PgConnection db = lab();
  RunShipper shipper(local.path(), "rig-a", "test");
  db.exec("ALTER TABLE samples ADD CONSTRAINT refuse_late_samples CHECK (idx < 35000)",
          "refuse the last pieces");
  EXPECT_THROW(shipper.ship_pass(db, 100000), LabArchiveError);
  EXPECT_EQ(
      server.query("SELECT (SELECT count(*) FROM samples) || ' ' || (SELECT count(*) FROM runs)"),
      "0 0");
  EXPECT_EQ(shipper.backlog().samples, 40000);
  db.exec("ALTER TABLE samples DROP CONSTRAINT refuse_late_samples", "accept every sample");
  EXPECT_EQ(shipper.ship_pass(db, 100000), 40000);
  EXPECT_EQ(shipper.ship_pass(db, 100000), 0);
  writer.finish(id);
  shipper.ship_pass(db, 100000);
  expect_exact_copy(server, local, "rig-a", id);
}

TEST_F(LabReplication, ACopyTheClientAbandonsStoresNothingAndTheConnectionGoesOn) {
  PgConnection db = lab();
  {
    PgTransaction tx(db);
    PgCopyIn copy(db, "COPY rigs (rig_id) FROM STDIN", "copy rigs");
    copy.put("rig-x\n");
  }  // abandoned, then rolled back
  EXPECT_EQ(db.query("SELECT count(*) FROM rigs", {}, "count rigs").integer(0, 0), 0);
  {
    PgTransaction tx(db);
    PgCopyIn copy(db, "COPY rigs (rig_id) FROM STDIN", "copy rigs");
    copy.put("rig-y\n");
    copy.finish();
    tx.commit();
  }
  EXPECT_EQ(server.query("SELECT string_agg(rig_id, ',') FROM rigs"), "rig-y");
}

TEST(LabArchivePassword, AFileOthersMayReadIsRefusedByName) {
  testing::ScratchDir dir("lab-password");
  const std::string file = dir.file("lab.password");
  std::ofstream(file) << "s3cret\n";
  chmod(file.c_str(), 0644);
  LabArchiveSettings s;
  s.password_file = file;
  try {
    connection_params(s);
    FAIL() << "a world-readable password file was accepted";
  } catch (const LabArchiveError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  file + ": lab_archive.password_file may be read by others (mode 644)"),
              std::string::npos)
        << e.what();
  }
  chmod(file.c_str(), 0600);
  const ConnectionParams params = connection_params(s);
  EXPECT_EQ(params.back(), (std::pair<std::string, std::string>{"password", "s3cret"}));
}

TEST_F(LabReplication, RunsOfSeveralRigsAreFoundByRigEyeLotDateAndMetadata) {
  PgConnection db = lab();
  for (const std::string rig : {"rig-a", "rig-b"}) {
    archive::Archive rig_archive(dir.file(rig + ".sqlite"));
    testing::LocalRunWriter rig_writer(rig_archive);
    for (const std::string lot : {"L1", "L2"}) {
      const std::int64_t id =
          rig_writer.start("E-" + rig + lot, lot, rig == "rig-a" ? "ann" : "bob");
      rig_writer.append(id, 50);
      rig_writer.finish(id);
    }
    RunShipper(rig_archive.path(), rig, "test").ship_pass(db, 100000);
  }
  LabRunReader reader(server.conninfo());
  auto count = [&reader](const std::vector<std::string>& filters) {
    LabRunFilter filter;
    for (const auto& f : filters) filter.add(f);
    return reader.list_runs(filter).size();
  };
  EXPECT_EQ(count({}), 4U);
  EXPECT_EQ(count({"rig=rig-b"}), 2U);
  EXPECT_EQ(count({"eye_lot=L2"}), 2U);
  EXPECT_EQ(count({"eye-lot=L2", "rig=rig-a"}), 1U);
  EXPECT_EQ(count({"operator=bob"}), 2U);
  EXPECT_EQ(count({"blade_lot=B-12", "eye_lot=L1"}), 2U);
  EXPECT_EQ(count({"since=2000-01-01"}), 4U);
  EXPECT_EQ(count({"since=2999-01-01"}), 0U);
  EXPECT_EQ(reader.list_runs({}).front().samples, 50);
  EXPECT_THROW(LabRunFilter().add("rig"), std::runtime_error);
}

}  // namespace
}  // namespace rig::lab_archive
