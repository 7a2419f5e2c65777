#pragma once
// The lab archive's schema on PostgreSQL: rigs, runs (every metadata field, extra metadata
// as jsonb), samples (natively partitioned by month of the run's creation, so a run never
// spans partitions), events, channels of imported runs, and the camera frame index.
// Versioned in lab_schema; every rigd and `rig` migrates an older schema on connect, under
// an advisory lock so several rigs starting together migrate once.
#include <string>

#include "pg_connection.hpp"

namespace rig::lab_archive {

inline constexpr int kLabSchemaVersion = 2;

// 0 when the database has no lab archive yet.
int lab_schema_version(PgConnection& db);
// Creates the current schema or migrates an older one; throws on a newer one (an older
// rigd must not write into a schema it does not know).
void create_or_migrate_lab_schema(PgConnection& db);
// Creates exactly the given (older) version: for the migration test and nothing else.
void create_lab_schema_version(PgConnection& db, int version);
// Makes sure the month partition of samples that holds `timestamp` (ISO 8601) exists.
void ensure_samples_partition(PgConnection& db, const std::string& timestamp);

}  // namespace rig::lab_archive
