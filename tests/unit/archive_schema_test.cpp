// The archive's schema version and forward migrations (daemon/archive/schema_migrations.hpp):
// an archive written by an older rigd opens, keeps its runs and gains the newer tables.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "archive.hpp"
#include "schema_migrations.hpp"
#include "test_paths.hpp"

namespace rig::archive {
namespace {

// The tables of the first archive (before camera frames), frozen here as a rig installed then
// created them: schema version 0 had them without a user_version, version 1 the same tables.
constexpr const char* kFirstTables = R"sql(
CREATE TABLE runs (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  eye_id TEXT NOT NULL, iop_mmHg REAL, velocity_mm_s REAL, depth_mm REAL, hold_s REAL,
  post_mortem_h REAL, operator TEXT, notes TEXT, config_hash TEXT, software_version TEXT,
  surface_mm REAL NOT NULL DEFAULT 0, rate_hz REAL,
  created_at TEXT NOT NULL, started_at TEXT, ended_at TEXT,
  outcome TEXT NOT NULL, reason TEXT, source TEXT NOT NULL);
CREATE TABLE run_meta (
  run_id INTEGER NOT NULL REFERENCES runs(id), seq INTEGER NOT NULL, key TEXT NOT NULL,
  value TEXT NOT NULL, PRIMARY KEY (run_id, seq));
CREATE TABLE samples (
  run_id INTEGER NOT NULL, idx INTEGER NOT NULL, t_s REAL NOT NULL, position_mm REAL NOT NULL,
  force_N REAL NOT NULL, iop_mmHg REAL, velocity_mm_s REAL, motor_V REAL, pump REAL,
  state INTEGER, phase INTEGER, io_ok INTEGER, PRIMARY KEY (run_id, idx)) WITHOUT ROWID;
CREATE TABLE channels (
  run_id INTEGER NOT NULL, name TEXT NOT NULL, data BLOB NOT NULL, PRIMARY KEY (run_id, name));
CREATE TABLE events (
  run_id INTEGER NOT NULL, t_s REAL NOT NULL, kind TEXT NOT NULL, message TEXT NOT NULL);
CREATE INDEX events_by_run ON events(run_id);
)sql";

// The first schema (before versions): what an archive from a rig installed then holds,
// user_version 0.
const std::string kFirstSchema = std::string(kFirstTables) + R"sql(
INSERT INTO runs (eye_id, iop_mmHg, velocity_mm_s, depth_mm, created_at, ended_at, outcome, source)
  VALUES ('E01', 15, 2, 14, '2026-01-05T10:00:00.000Z', '2026-01-05T10:00:09.000Z', 'completed', 'rig');
INSERT INTO samples (run_id, idx, t_s, position_mm, force_N) VALUES (1, 0, 0.000, 20.0, 0.00), (1, 1, 0.001, 20.002, 0.01);
INSERT INTO events (run_id, t_s, kind, message) VALUES (1, 0.001, 'contact', 'first contact');
)sql";

bool has_table(Database& db, const std::string& name) {
  Statement q = db.prepare("SELECT 1 FROM sqlite_master WHERE type='table' AND name=?");
  q.bind(1, name);
  return q.step();
}

TEST(ArchiveSchema, AnArchiveFromTheFirstSchemaIsMigratedForwardAndKeepsItsRuns) {
  testing::ScratchDir dir("archive-schema-old");
  const std::string path = dir.file("old.sqlite");
  {
    Database old(path, false);
    old.exec(kFirstSchema);
    ASSERT_EQ(SchemaMigrations::version_of(old), 0);
    ASSERT_FALSE(has_table(old, "frames"));
  }
  Archive archive(path);
  Database check(path, true);
  EXPECT_EQ(SchemaMigrations::version_of(check), SchemaMigrations::kCurrentVersion);
  EXPECT_TRUE(has_table(check, "frames"));
  const auto run = archive.find_run(1);
  ASSERT_TRUE(run.has_value());
  EXPECT_EQ(run->eye_id, "E01");
  EXPECT_EQ(run->outcome, "completed");
  EXPECT_EQ(run->samples, 2);
  // The new table takes rows: a camera frame of the old run.
  FrameRow frame;
  frame.run_id = 1;
  frame.sample_index = 1;
  frame.file = "run-1.frames";
  frame.bytes = 76800;
  frame.width = 320;
  frame.height = 240;
  archive.add_frame(frame);
  EXPECT_EQ(archive.run_frames(1).size(), 1U);
}

// An archive of schema version 1 (the previous one, before camera frames): the version-1 tables
// as daemon/archive/schema_migrations.cpp creates them, user_version 1, and two runs with
// metadata, 500 samples each, a channel and events.
const std::string kVersion1Archive = std::string(kFirstTables) + R"sql(
INSERT INTO runs (eye_id, iop_mmHg, velocity_mm_s, depth_mm, hold_s, operator, surface_mm, rate_hz, created_at,
                  started_at, ended_at, outcome, reason, source) VALUES
  ('E11', 15, 2, 14, 0, 'ab', 20, 1000, '2026-06-01T09:00:00.000Z', '2026-06-01T09:00:02.000Z',
   '2026-06-01T09:00:11.000Z', 'completed', NULL, 'rig'),
  ('E12', 18, 1, 10, 2, 'cd', 20, 1000, '2026-06-01T10:00:00.000Z', '2026-06-01T10:00:02.000Z',
   '2026-06-01T10:00:05.000Z', 'fault', 'force limit exceeded: 2.100 N', 'rig');
INSERT INTO run_meta (run_id, seq, key, value) VALUES (1, 0, 'blade', 'K-3'), (2, 0, 'blade', 'K-4'), (2, 1, 'temp_C', '21.5');
WITH RECURSIVE i(n) AS (SELECT 0 UNION ALL SELECT n + 1 FROM i WHERE n < 499)
INSERT INTO samples (run_id, idx, t_s, position_mm, force_N, iop_mmHg, velocity_mm_s, motor_V, pump, state, phase, io_ok)
  SELECT r.id, n, n * 0.001, 18 + n * 0.002, n * 0.0007 + r.id, r.iop_mmHg, 2, 1.5, 0.375, 4, 2, 1 FROM i, runs r;
INSERT INTO channels (run_id, name, data) VALUES (1, 'acoustic_V', X'000000000000F03F0000000000000040');
INSERT INTO events (run_id, t_s, kind, message) VALUES (1, 0.2, 'contact', '20.01'), (1, 0.5, 'run_ended', 'completed'),
  (2, 0.3, 'fault', 'force limit exceeded: 2.100 N'), (2, 0.3, 'run_ended', 'fault');
PRAGMA user_version = 1;
)sql";

// Every row of `table`, each as one text (SQLite's quote() of each column), in a fixed order.
std::vector<std::string> rows_of(Database& db, const std::string& table) {
  std::string columns;
  Statement names = db.prepare("SELECT name FROM pragma_table_info(?)");
  names.bind(1, table);
  while (names.step())
    columns += (columns.empty() ? "quote(" : " || '|' || quote(") + names.text(0) + ")";
  std::vector<std::string> rows;
  Statement all = db.prepare("SELECT " + columns + " FROM " + table + " ORDER BY 1");
  while (all.step()) rows.push_back(all.text(0));
  return rows;
}

// The schema's objects (tables, indexes) by name, with the SQL that made them.
std::map<std::string, std::string> schema_of(Database& db) {
  std::map<std::string, std::string> objects;
  Statement q = db.prepare("SELECT name, coalesce(sql, '') FROM sqlite_master");
  while (q.step()) objects[q.text(0)] = q.text(1);
  return objects;
}

TEST(ArchiveSchema, AnArchiveAtVersion1GainsOnlyTheFramesTableAndKeepsEveryRunSampleAndEvent) {
  testing::ScratchDir dir("archive-schema-v1");
  const std::string path = dir.file("v1.sqlite");
  const std::vector<std::string> tables = {"runs", "run_meta", "samples", "channels", "events"};
  std::map<std::string, std::vector<std::string>> before;
  std::map<std::string, std::string> schema_before;
  {
    Database v1(path, false);
    v1.exec(kVersion1Archive);
    ASSERT_EQ(SchemaMigrations::version_of(v1), 1);
    for (const auto& table : tables) before[table] = rows_of(v1, table);
    schema_before = schema_of(v1);
  }
  ASSERT_EQ(before["samples"].size(), 1000U);
  ASSERT_EQ(before["events"].size(), 4U);
  Archive archive(path);  // the v1 -> v2 step, and no other, runs here
  Database check(path, true);
  EXPECT_EQ(SchemaMigrations::version_of(check), SchemaMigrations::kCurrentVersion);
  for (const auto& table : tables)
    EXPECT_EQ(rows_of(check, table), before[table]) << "table " << table << " changed";
  // The step adds the frames table and leaves every version-1 object as it was.
  std::map<std::string, std::string> schema_after = schema_of(check);
  ASSERT_EQ(schema_after.count("frames"), 1U)
      << "the v1 -> v2 step did not create the frames table";
  schema_after.erase("frames");
  EXPECT_EQ(schema_after, schema_before);
  // Through the archive: the runs read back whole and take camera frames.
  const auto run = archive.find_run(2);
  ASSERT_TRUE(run.has_value());
  EXPECT_EQ(run->outcome, "fault");
  EXPECT_EQ(run->samples, 500);
  EXPECT_EQ(archive.load_run(1).size(), 500U);
  FrameRow frame;
  frame.run_id = 1;
  frame.sample_index = 499;
  frame.file = "run-1.frames";
  frame.bytes = 76800;
  frame.width = 320;
  frame.height = 240;
  archive.add_frame(frame);
  EXPECT_EQ(archive.run_frames(1).size(), 1U);
}

TEST(ArchiveSchema, ANewArchiveStartsAtTheCurrentVersionAndReopensWithoutChange) {
  testing::ScratchDir dir("archive-schema-new");
  const std::string path = dir.file("new.sqlite");
  { Archive created(path); }
  { Archive reopened(path); }
  Database check(path, true);
  EXPECT_EQ(SchemaMigrations::version_of(check), SchemaMigrations::kCurrentVersion);
}

TEST(ArchiveSchema, AnArchiveFromANewerRigdIsRefusedWithBothVersionsNamed) {
  testing::ScratchDir dir("archive-schema-newer");
  const std::string path = dir.file("newer.sqlite");
  { Archive created(path); }
  {
    Database db(path, false);
    db.exec("PRAGMA user_version = 99");
  }
  for (const bool read_only : {false, true}) {
    try {
      Archive refused(path, read_only);
      ADD_FAILURE() << "an archive of schema version 99 was opened";
    } catch (const ArchiveError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path), std::string::npos) << what;
      EXPECT_NE(what.find("99"), std::string::npos) << what;
      EXPECT_NE(what.find(std::to_string(SchemaMigrations::kCurrentVersion)), std::string::npos)
          << what;
    }
  }
}

}  // namespace
}  // namespace rig::archive
