#include "lab_run_reader.hpp"

#include <sstream>
#include <stdexcept>

namespace rig::lab_archive {
namespace {

// UTC ISO 8601 with milliseconds, as the local archive writes its timestamps.
std::string iso(const std::string& column) {
  return "to_char(" + column + " AT TIME ZONE 'UTC', 'YYYY-MM-DD\"T\"HH24:MI:SS.MS\"Z\"')";
}

std::string format_number(double value) {
  std::ostringstream out;
  out.precision(10);
  out << value;
  return out.str();
}

std::optional<double> maybe_real(const PgResult& rows, int row, int column) {
  if (rows.is_null(row, column)) return std::nullopt;
  return rows.real(row, column);
}

// Metadata keys that are columns of runs; any other key is looked up in runs.meta.
const char* column_of(const std::string& key) {
  static const char* const kColumns[] = {"eye_id", "operator", "outcome", "source", "config_hash", "software_version"};
  for (const char* column : kColumns) {
    if (key == column) return column;
  }
  return nullptr;
}

}  // namespace

void LabRunFilter::add(const std::string& key_value) {
  const auto eq = key_value.find('=');
  if (eq == std::string::npos || eq == 0) throw std::runtime_error(key_value + ": expected a lab archive filter key=value");
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
  std::string sql = "SELECT run_uuid, rig_id, local_run_id, eye_id, coalesce(eye_lot, ''), iop_mmhg, velocity_mm_s, depth_mm, " +
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
  for (int r = 0; r < rows.rows(); ++r) {
    runs.push_back({rows.text(r, 0), rows.text(r, 1), rows.integer(r, 2), rows.text(r, 3), rows.text(r, 4),
                    maybe_real(rows, r, 5), maybe_real(rows, r, 6), maybe_real(rows, r, 7), rows.text(r, 8),
                    rows.text(r, 9), rows.text(r, 10), rows.text(r, 11), rows.integer(r, 12)});
  }
  return runs;
}

std::vector<std::pair<std::string, std::string>> LabRunReader::run_meta(const std::string& run_uuid, double& surface_mm,
                                                                         bool& from_rig) {
  PgResult q = db_.query("SELECT eye_id, iop_mmhg, velocity_mm_s, depth_mm, hold_s, post_mortem_h, operator, notes,"
                         " config_hash, software_version, " + iso("started_at") + ", outcome, reason, source, surface_mm,"
                         " local_run_id, rig_id, run_uuid, (SELECT string_agg(key || chr(31) || value, chr(30)"
                         " ORDER BY ord) FROM jsonb_each_text(meta) WITH ORDINALITY AS m(key, value, ord))"
                         " FROM runs WHERE run_uuid = $1",
                         {run_uuid}, "read run " + run_uuid);
  if (q.rows() == 0) throw LabArchiveError("lab archive: no run " + run_uuid);
  const char* names[] = {"eye_id", "iop_mmHg", "velocity_mm_s", "depth_mm", "hold_s", "post_mortem_h", "operator",
                         "notes", "config_hash", "software_version", "started_at", "outcome", "reason", "source"};
  std::vector<std::pair<std::string, std::string>> meta;
  for (int i = 0; i < 14; ++i) {
    if (q.is_null(0, i)) continue;
    const bool numeric = i >= 1 && i <= 5;
    std::string value = numeric ? format_number(q.real(0, i)) : q.text(0, i);
    if (!value.empty()) meta.emplace_back(names[i], value);
  }
  surface_mm = q.real(0, 14);
  from_rig = q.text(0, 13) == "rig";
  meta.emplace_back("run_id", q.text(0, 15));
  meta.emplace_back("rig_id", q.text(0, 16));
  meta.emplace_back("run_uuid", q.text(0, 17));
  std::istringstream extra(q.text(0, 18));
  for (std::string pair; std::getline(extra, pair, '\x1e');) {
    const auto cut = pair.find('\x1f');
    if (cut != std::string::npos) meta.emplace_back(pair.substr(0, cut), pair.substr(cut + 1));
  }
  return meta;
}

model::RunData LabRunReader::load_run(const std::string& run_uuid) {
  model::RunData run;
  run.source = "lab archive run " + run_uuid;
  double surface_mm = 0.0;
  bool from_rig = false;
  run.meta = run_meta(run_uuid, surface_mm, from_rig);
  PgResult q = db_.query("SELECT t_s, position_mm, force_n, iop_mmhg, motor_v, velocity_mm_s FROM samples"
                         " WHERE run_uuid = $1 ORDER BY idx", {run_uuid}, "read the samples of run " + run_uuid);
  const int n = q.rows();
  const double t0 = from_rig && n > 0 ? q.real(0, 0) : 0.0;
  model::Channel iop{"iop_meas_mmHg", {}}, motor{"motor_cmd_V", {}}, velocity{"velocity_meas_mm_s", {}};
  for (int r = 0; r < n; ++r) {
    run.t_s.push_back(q.real(r, 0) - t0);
    run.x_mm.push_back(q.real(r, 1) - surface_mm);
    run.force_N.push_back(q.real(r, 2));
    if (!from_rig) continue;
    iop.values.push_back(q.real(r, 3));
    motor.values.push_back(q.real(r, 4));
    velocity.values.push_back(q.real(r, 5));
  }
  if (from_rig) {
    run.channels = {std::move(iop), std::move(motor), std::move(velocity)};
  } else {
    load_channels(run_uuid, run);
  }
  return run;
}

void LabRunReader::load_channels(const std::string& run_uuid, model::RunData& run) {
  PgResult ch = db_.query("SELECT name, array_to_string(data, ',') FROM channels WHERE run_uuid = $1 ORDER BY seq",
                          {run_uuid}, "read the channels of run " + run_uuid);
  for (int r = 0; r < ch.rows(); ++r) {
    model::Channel channel{ch.text(r, 0), {}};
    std::istringstream values(ch.text(r, 1));
    for (std::string value; std::getline(values, value, ',');) channel.values.push_back(std::stod(value));
    run.channels.push_back(std::move(channel));
  }
}

}  // namespace rig::lab_archive
