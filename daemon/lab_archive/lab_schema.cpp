#include "lab_schema.hpp"

#include <cstdio>

namespace rig::lab_archive {
namespace {

// Advisory lock key for schema changes and partition creation ("LABA" in ASCII).
constexpr const char* kSchemaLock = "SELECT pg_advisory_xact_lock(1279345217)";

// Version 1: rigs, runs, samples, events, channels.
constexpr const char* kSchemaV1 = R"sql(
CREATE TABLE lab_schema (version integer NOT NULL);
CREATE TABLE rigs (
  rig_id text PRIMARY KEY, first_seen timestamptz NOT NULL DEFAULT now(),
  last_seen timestamptz NOT NULL DEFAULT now(), software_version text);
CREATE TABLE runs (
  run_uuid uuid PRIMARY KEY, rig_id text NOT NULL REFERENCES rigs(rig_id), local_run_id bigint NOT NULL,
  eye_id text NOT NULL, iop_mmhg double precision, velocity_mm_s double precision, depth_mm double precision,
  hold_s double precision, post_mortem_h double precision, operator text, notes text, config_hash text,
  software_version text, surface_mm double precision NOT NULL DEFAULT 0, rate_hz double precision,
  created_at timestamptz NOT NULL, started_at timestamptz, ended_at timestamptz,
  outcome text NOT NULL, reason text, source text NOT NULL, meta jsonb NOT NULL DEFAULT '{}',
  last_idx bigint NOT NULL DEFAULT -1, samples bigint NOT NULL DEFAULT 0, events bigint NOT NULL DEFAULT 0,
  replicated_at timestamptz NOT NULL DEFAULT now());
CREATE INDEX runs_by_rig ON runs (rig_id, local_run_id);
CREATE INDEX runs_by_created ON runs (created_at);
CREATE INDEX runs_by_meta ON runs USING gin (meta jsonb_path_ops);
CREATE TABLE samples (
  run_uuid uuid NOT NULL, run_created_at timestamptz NOT NULL, idx bigint NOT NULL,
  t_s double precision NOT NULL, position_mm double precision NOT NULL, force_n double precision NOT NULL,
  iop_mmhg double precision, velocity_mm_s double precision, motor_v double precision, pump double precision,
  state smallint, phase smallint, io_ok smallint,
  PRIMARY KEY (run_uuid, idx, run_created_at)) PARTITION BY RANGE (run_created_at);
CREATE TABLE events (
  run_uuid uuid NOT NULL REFERENCES runs(run_uuid), seq bigint NOT NULL, t_s double precision NOT NULL,
  kind text NOT NULL, message text NOT NULL, PRIMARY KEY (run_uuid, seq));
CREATE TABLE channels (
  run_uuid uuid NOT NULL REFERENCES runs(run_uuid), seq integer NOT NULL, name text NOT NULL,
  data double precision[] NOT NULL, PRIMARY KEY (run_uuid, seq));
INSERT INTO lab_schema (version) VALUES (1);
)sql";

// Version 2: the eye lot as a column of its own (indexed: "all runs of eye lot X") and the
// camera frame index.
constexpr const char* kMigrateV1ToV2 = R"sql(
ALTER TABLE runs ADD COLUMN eye_lot text;
UPDATE runs SET eye_lot = meta->>'eye_lot';
CREATE INDEX runs_by_eye_lot ON runs (eye_lot, created_at);
ALTER TABLE runs ADD COLUMN frames bigint NOT NULL DEFAULT 0;
CREATE TABLE frames (
  run_uuid uuid NOT NULL REFERENCES runs(run_uuid), frame_no bigint NOT NULL, sample_index bigint NOT NULL,
  camera_ts_ns bigint NOT NULL, host_ts_ns bigint NOT NULL, file text NOT NULL, file_offset bigint NOT NULL,
  bytes bigint NOT NULL, width integer NOT NULL, height integer NOT NULL, PRIMARY KEY (run_uuid, frame_no));
UPDATE lab_schema SET version = 2;
)sql";

void migrate_from(PgConnection& db, int version) {
  if (version < 1) db.exec(kSchemaV1, "create the lab archive schema (version 1)");
  if (version < 2) db.exec(kMigrateV1ToV2, "migrate the lab archive schema from version 1 to 2");
}

}  // namespace

int lab_schema_version(PgConnection& db) {
  PgResult exists = db.query("SELECT to_regclass('lab_schema') IS NOT NULL", {},
                             "look for the lab archive schema");
  if (exists.text(0, 0) != "t") return 0;
  PgResult version =
      db.query("SELECT max(version) FROM lab_schema", {}, "read the lab archive schema version");
  return version.is_null(0, 0) ? 0 : static_cast<int>(version.integer(0, 0));
}

void create_or_migrate_lab_schema(PgConnection& db) {
  PgTransaction tx(db);
  db.exec(kSchemaLock, "lock the lab archive schema");
  const int version = lab_schema_version(db);
  if (version > kLabSchemaVersion) {
    throw LabArchiveError("lab archive: the database has schema version " +
                          std::to_string(version) + ", newer than this rigd's " +
                          std::to_string(kLabSchemaVersion) + "; update rigd");
  }
  migrate_from(db, version);
  tx.commit();
}

void create_lab_schema_version(PgConnection& db, int version) {
  PgTransaction tx(db);
  if (version >= 1) db.exec(kSchemaV1, "create the lab archive schema (version 1)");
  if (version >= 2) db.exec(kMigrateV1ToV2, "migrate the lab archive schema from version 1 to 2");
  tx.commit();
}

void ensure_samples_partition(PgConnection& db, const std::string& timestamp) {
  int year = 0, month = 0;
  if (std::sscanf(timestamp.c_str(), "%4d-%2d", &year, &month) != 2 || month < 1 || month > 12) {
    throw LabArchiveError("lab archive: run timestamp '" + timestamp + "' is not ISO 8601");
  }
  const int next_year = month == 12 ? year + 1 : year;
  const int next_month = month == 12 ? 1 : month + 1;
  char sql[320];
  std::snprintf(sql, sizeof sql,
                "CREATE TABLE IF NOT EXISTS samples_%04d_%02d PARTITION OF samples FOR VALUES FROM "
                "('%04d-%02d-01 00:00:00+00') TO ('%04d-%02d-01 00:00:00+00')",
                year, month, year, month, next_year, next_month);
  PgTransaction tx(db);
  db.exec(kSchemaLock, "lock the lab archive schema");
  db.exec(sql, "create the samples partition for " + timestamp.substr(0, 7));
  tx.commit();
}

}  // namespace rig::lab_archive
