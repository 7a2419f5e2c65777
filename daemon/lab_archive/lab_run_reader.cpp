#include "lab_run_reader.hpp"

#include <stdexcept>

#include "lab_row_decoder.hpp"

namespace rig::lab_archive {
namespace {

// UTC ISO 8601 with milliseconds, as the local archive writes its timestamps.
std::string iso(const std::string& column) {
  return "to_char(" + column + " AT TIME ZONE 'UTC', 'YYYY-MM-DD\"T\"HH24:MI:SS.MS\"Z\"')";
}

// Metadata keys that are columns of runs; any other key is looked up in runs.meta.
const char* column_of(const std::string& key) {
  static const char* const kColumns[] = {"eye_id", "operator",    "outcome",
                                         "source", "config_hash", "software_version"};
  for (const char* column : kColumns) {
    if (key == column) return column;
  }
  return nullptr;
}

}  // namespace

void LabRunFilter::add(const std::string& key_value) {
  const auto eq = key_value.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::runtime_error(key_value + ": expected a lab archive filter key=value");
  const std::string key = key_value.substr(0, eq);
  const std::string value = key_value.substr(eq + 1);
  if (key == "rig") {
    rig = value;
  } else if (key == "eye_lot" || key == "eye-lot") {
    eye_lot = value;
  } else if (key == "since") {
    since = value;
  } else if (key == "run") {
    run = value;
  } else {
    meta.emplace_back(key, value);
  }
}

LabRunReader::LabRunReader(const std::string& conninfo) : db_(conninfo) {}
LabRunReader::LabRunReader(const ConnectionParams& params) : db_(params) {}

std::vector<LabRunRow> LabRunReader::list_runs(const LabRunFilter& filter) {
  std::string sql =
      "SELECT run_uuid, rig_id, local_run_id, eye_id, coalesce(eye_lot, ''), iop_mmhg, "
      "velocity_mm_s, depth_mm, " +
      iso("coalesce(started_at, created_at)") + ", coalesce(" + iso("ended_at") +
      ", ''), outcome, source, samples FROM runs WHERE true";
  std::vector<std::string> params;
  auto where = [&](const std::string& condition, const std::string& value) {
    params.push_back(value);
    sql += " AND " + condition + "$" + std::to_string(params.size());
  };
  if (!filter.rig.empty()) where("rig_id = ", filter.rig);
  if (!filter.eye_lot.empty()) where("eye_lot = ", filter.eye_lot);
  if (!filter.since.empty()) where("created_at >= ", filter.since);
  if (!filter.run.empty()) where("run_uuid = ", filter.run);
  for (const auto& [key, value] : filter.meta) {
    if (const char* column = column_of(key)) {
      where(std::string(column) + " = ", value);
    } else {
      params.push_back(key);
      where("meta->>$" + std::to_string(params.size()) + " = ", value);
    }
  }
  sql += " ORDER BY created_at, rig_id, local_run_id";
  PgResult rows = db_.query(sql, params, "list runs");
  std::vector<LabRunRow> runs;
  runs.reserve(static_cast<std::size_t>(rows.rows()));
  for (int r = 0; r < rows.rows(); ++r) runs.push_back(decode_run_row(rows, r));
  return runs;
}

model::RunData LabRunReader::load_run(const std::string& run_uuid) {
  const PgResult meta = db_.query(
      "SELECT eye_id, iop_mmhg, velocity_mm_s, depth_mm, hold_s, post_mortem_h, operator, notes,"
      " config_hash, software_version, " +
          iso("started_at") +
          ", outcome, reason, source, surface_mm,"
          " local_run_id, rig_id, run_uuid, (SELECT string_agg(key || chr(31) || value, chr(30)"
          " ORDER BY ord) FROM jsonb_each_text(meta) WITH ORDINALITY AS m(key, value, ord))"
          " FROM runs WHERE run_uuid = $1",
      {run_uuid}, "read run " + run_uuid);
  const bool from_rig = lab_run_from_rig(meta, run_uuid);
  const PgResult samples = db_.query(
      "SELECT t_s, position_mm, force_n, iop_mmhg, motor_v, velocity_mm_s FROM samples"
      " WHERE run_uuid = $1 ORDER BY idx",
      {run_uuid}, "read the samples of run " + run_uuid);
  if (from_rig) return decode_lab_run(run_uuid, meta, samples, nullptr);
  const PgResult channels = db_.query(
      "SELECT name, array_to_string(data, ',') FROM channels WHERE run_uuid = $1 ORDER BY seq",
      {run_uuid}, "read the channels of run " + run_uuid);
  return decode_lab_run(run_uuid, meta, samples, &channels);
}

}  // namespace rig::lab_archive
