// The lab archive's schema on a real PostgreSQL 15 (throwaway server): creation, native
// partitioning, indexes, migration from the previous version, and refusal of a newer one.
#include <gtest/gtest.h>

#include "lab_schema.hpp"
#include "pg_test_server.hpp"

namespace rig::lab_archive {
namespace {

TEST(LabSchema, ANewDatabaseGetsTheCurrentSchemaWithSamplesPartitionedByMonth) {
  testing::PgTestServer server;
  PgConnection db(server.conninfo());
  EXPECT_EQ(lab_schema_version(db), 0);
  create_or_migrate_lab_schema(db);
  EXPECT_EQ(lab_schema_version(db), kLabSchemaVersion);
  EXPECT_EQ(server.query("SELECT relkind FROM pg_class WHERE relname = 'samples'"), "p");
  ensure_samples_partition(db, "2026-12-31T23:59:59.999Z");
  ensure_samples_partition(db, "2026-12-01T00:00:00.000Z");  // again: no error, no second partition
  EXPECT_EQ(
      server.query(
          "SELECT string_agg(c.relname || ' ' || pg_get_expr(c.relpartbound, c.oid), '|') FROM "
          "pg_inherits i"
          " JOIN pg_class c ON c.oid = i.inhrelid WHERE i.inhparent = 'samples'::regclass"),
      "samples_2026_12 FOR VALUES FROM ('2026-12-01 00:00:00+00') TO ('2027-01-01 00:00:00+00')");
}

TEST(LabSchema, RunsOfAnEyeLotAndSamplesOfARunAreIndexed) {
  testing::PgTestServer server;
  PgConnection db(server.conninfo());
  create_or_migrate_lab_schema(db);
  const std::string indexes = server.query(
      "SELECT string_agg(indexdef, '|' ORDER BY indexname) FROM pg_indexes WHERE tablename IN "
      "('runs', 'samples')");
  EXPECT_NE(indexes.find("runs_by_eye_lot ON public.runs USING btree (eye_lot, created_at)"),
            std::string::npos)
      << indexes;
  EXPECT_NE(indexes.find(
                "samples_pkey ON ONLY public.samples USING btree (run_uuid, idx, run_created_at)"),
            std::string::npos)
      << indexes;
  const std::string plan = server.psql(
      "lab", "SET enable_seqscan = off; EXPLAIN SELECT run_uuid FROM runs WHERE eye_lot = 'L7'");
  EXPECT_NE(plan.find("runs_by_eye_lot"), std::string::npos) << plan;
}

TEST(LabSchema, AVersionOneArchiveIsMigratedAndKeepsItsRuns) {
  testing::PgTestServer server;
  PgConnection db(server.conninfo());
  create_lab_schema_version(db, 1);
  ASSERT_EQ(lab_schema_version(db), 1);
  server.query(
      "INSERT INTO rigs (rig_id) VALUES ('rig-a');"
      "INSERT INTO runs (run_uuid, rig_id, local_run_id, eye_id, created_at, outcome, source, "
      "meta) VALUES"
      " ('8b0e9a52-61f3-8e4a-9d3c-2f8a6b1c0d11', 'rig-a', 1, 'E01', '2026-11-02T10:00:00Z', "
      "'completed', 'rig',"
      " '{\"eye_lot\": \"L7\", \"blade_lot\": \"B-12\"}')");
  create_or_migrate_lab_schema(db);
  EXPECT_EQ(lab_schema_version(db), 2);
  EXPECT_EQ(
      server.query("SELECT eye_id || ' ' || eye_lot || ' ' || (meta->>'blade_lot') FROM runs"),
      "E01 L7 B-12");
  EXPECT_EQ(server.query("SELECT count(*) FROM frames"), "0");
  create_or_migrate_lab_schema(db);  // a second rigd connecting: nothing to do
  EXPECT_EQ(server.query("SELECT count(*) FROM lab_schema"), "1");
}

TEST(LabSchema, ASchemaNewerThanThisRigdIsRefusedWithItsVersion) {
  testing::PgTestServer server;
  PgConnection db(server.conninfo());
  create_or_migrate_lab_schema(db);
  server.query("UPDATE lab_schema SET version = 99");
  try {
    create_or_migrate_lab_schema(db);
    FAIL() << "a newer schema was accepted";
  } catch (const LabArchiveError& e) {
    EXPECT_NE(std::string(e.what()).find("schema version 99, newer than this rigd's 2"),
              std::string::npos)
        << e.what();
  }
}

TEST(LabSchema, AnUnreachableServerIsReportedWithoutTheConnectionString) {
  const int port = testing::PgTestServer::free_port();
  try {
    PgConnection db("host=127.0.0.1 port=" + std::to_string(port) +
                    " user=postgres password=s3cret connect_timeout=2");
    FAIL() << "connected to nothing";
  } catch (const LabArchiveError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("connect to the lab archive"), std::string::npos) << message;
    EXPECT_EQ(message.find("s3cret"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace rig::lab_archive
