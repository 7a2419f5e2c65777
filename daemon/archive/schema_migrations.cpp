#include "schema_migrations.hpp"

#include <string>

namespace rig::archive {
namespace {

// Version 1: runs, their metadata, samples, extra channels and events (the first archive).
constexpr std::string_view kVersion1 = R"sql(
CREATE TABLE IF NOT EXISTS runs (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  eye_id TEXT NOT NULL, iop_mmHg REAL, velocity_mm_s REAL, depth_mm REAL, hold_s REAL,
  post_mortem_h REAL, operator TEXT, notes TEXT, config_hash TEXT, software_version TEXT,
  surface_mm REAL NOT NULL DEFAULT 0, rate_hz REAL,
  created_at TEXT NOT NULL, started_at TEXT, ended_at TEXT,
  outcome TEXT NOT NULL, reason TEXT, source TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS run_meta (
  run_id INTEGER NOT NULL REFERENCES runs(id), seq INTEGER NOT NULL, key TEXT NOT NULL,
  value TEXT NOT NULL, PRIMARY KEY (run_id, seq));
CREATE TABLE IF NOT EXISTS samples (
  run_id INTEGER NOT NULL, idx INTEGER NOT NULL, t_s REAL NOT NULL, position_mm REAL NOT NULL,
  force_N REAL NOT NULL, iop_mmHg REAL, velocity_mm_s REAL, motor_V REAL, pump REAL,
  state INTEGER, phase INTEGER, io_ok INTEGER, PRIMARY KEY (run_id, idx)) WITHOUT ROWID;
CREATE TABLE IF NOT EXISTS channels (
  run_id INTEGER NOT NULL, name TEXT NOT NULL, data BLOB NOT NULL, PRIMARY KEY (run_id, name));
CREATE TABLE IF NOT EXISTS events (
  run_id INTEGER NOT NULL, t_s REAL NOT NULL, kind TEXT NOT NULL, message TEXT NOT NULL);
CREATE INDEX IF NOT EXISTS events_by_run ON events(run_id);
)sql";

// Version 2: camera frames, each tied to the sample of its trigger (docs/camera.md).
constexpr std::string_view kVersion2 = R"sql(
CREATE TABLE IF NOT EXISTS frames (
  run_id INTEGER NOT NULL, frame_no INTEGER NOT NULL, sample_index INTEGER NOT NULL,
  camera_ts_ns INTEGER NOT NULL, host_ts_ns INTEGER NOT NULL, file TEXT NOT NULL,
  file_offset INTEGER NOT NULL, bytes INTEGER NOT NULL, width INTEGER NOT NULL, height INTEGER NOT NULL,
  PRIMARY KEY (run_id, frame_no)) WITHOUT ROWID;
)sql";

}  // namespace

std::string_view SchemaMigrations::migration_sql(int to_version) {
  switch (to_version) {
    case 1:
      return kVersion1;
    case 2:
      return kVersion2;
    default:
      return {};
  }
}

int SchemaMigrations::version_of(Database& db) {
  Statement q = db.prepare("PRAGMA user_version");
  return q.step() ? static_cast<int>(q.integer(0)) : 0;
}

void SchemaMigrations::check_readable(Database& db) {
  const int version = version_of(db);
  if (version > kCurrentVersion) {
    throw ArchiveError("archive " + db.path() + ": schema version " + std::to_string(version) +
                       " is newer than this rigd's (" + std::to_string(kCurrentVersion) +
                       "): update rigd");
  }
}

void SchemaMigrations::bring_up_to_date(Database& db) {
  check_readable(db);
  for (int to = version_of(db) + 1; to <= kCurrentVersion; ++to) {
    db.exec("BEGIN IMMEDIATE");
    try {
      if (version_of(db) < to) {  // another process may have migrated since we looked
        db.exec(std::string(migration_sql(to)));
        db.exec("PRAGMA user_version = " + std::to_string(to));
      }
      db.exec("COMMIT");
    } catch (...) {
      try {
        db.exec("ROLLBACK");
      } catch (const ArchiveError&) {  // the first error is the one to report
      }
      throw;
    }
  }
}

}  // namespace rig::archive
