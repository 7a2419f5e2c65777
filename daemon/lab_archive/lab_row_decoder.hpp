#pragma once
// The lab archive's query results (libpq text format) turned into runs: what the server sends
// is decoded here, without a connection, so the decoding is fuzzed on its own
// (tests/fuzz/fuzz_lab_archive_rows.cpp). The column orders are LabRunReader's queries'.
// Anything that does not decode throws LabArchiveError naming the run and the column.
#include <string>
#include <utility>
#include <vector>

#include "lab_run_reader.hpp"
#include "pg_connection.hpp"
#include "run_data.hpp"

namespace rig::lab_archive {

// One row of the run list (run_uuid, rig_id, local_run_id, eye_id, eye_lot, iop_mmhg,
// velocity_mm_s, depth_mm, started_at, ended_at, outcome, source, samples).
LabRunRow decode_run_row(const PgResult& rows, int row);

// Whether the run (the one row of the metadata query) was cut on a rig: its samples then
// carry IOP, motor and velocity; otherwise its channels are its own. Throws if there is no row.
bool lab_run_from_rig(const PgResult& meta, const std::string& run_uuid);

// The run as run-CSV data, as the local archive gives it. meta: the metadata query's row
// (eye_id .. source, surface_mm, local_run_id, rig_id, run_uuid, extra metadata joined by
// chr(30) between pairs and chr(31) between key and value); samples: t_s, position_mm,
// force_n, iop_mmhg, motor_v, velocity_mm_s by idx; channels (runs not from a rig): name and
// its values joined by ','. Every channel must have one value per sample.
model::RunData decode_lab_run(const std::string& run_uuid, const PgResult& meta,
                              const PgResult& samples, const PgResult* channels);

// "k1<US>v1<RS>k2<US>v2...": pairs without a separator are skipped.
std::vector<std::pair<std::string, std::string>> split_extra_meta(const std::string& joined);

}  // namespace rig::lab_archive
