// The archive's schema version and forward migrations (daemon/archive/schema_migrations.hpp):
// an archive written by an older rigd opens, keeps its runs and gains the newer tables.
#include <gtest/gtest.h>

#include "archive.hpp"
#include "schema_migrations.hpp"
#include "test_paths.hpp"

namespace rig::archive {
namespace {

// The schema of the first archive (before camera frames and before versions): what an
// archive from a rig installed then holds, user_version 0.
constexpr const char* kFirstSchema = R"sql(
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
      EXPECT_NE(what.find(std::to_string(SchemaMigrations::kCurrentVersion)), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace rig::archive
